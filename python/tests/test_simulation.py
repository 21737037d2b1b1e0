"""Simulations from Python: against the command line, a controller written in Python,
actuation, state access, and physics checks of single steps."""

import json
import subprocess

import numpy as np
import pytest

import hopsim

#: Summary figures that are the machine's, not the run's.
TIMING = ("wall_time_s", "steps_per_s")


def without_timing(summary):
    return {k: v for k, v in summary.items() if k not in TIMING}


@pytest.fixture(scope="module")
def cli_run(hopsim_bin, robbit_path, tmp_path_factory):
    """`hopsim run` of Robbit for 1 s: its MCAP recording and its summary."""
    out = tmp_path_factory.mktemp("cli")
    mcap, summary = out / "robbit.mcap", out / "robbit.json"
    subprocess.run(
        [hopsim_bin, "run", str(robbit_path), "--duration", "2", "--quiet"]
        + ["--mcap", str(mcap), "--summary", str(summary)],
        check=True,
    )
    return hopsim.read_mcap(mcap), json.loads(summary.read_text())


def test_step_by_step_equals_the_command_line(robbit, cli_run):
    recording, _ = cli_run
    sim = hopsim.Simulation(robbit)
    states = {0: (sim.t, sim.q, sim.u)}
    last = int(recording.steps[-1])
    for _ in range(last):
        sim.step()
        states[sim.step_count] = (sim.t, sim.q, sim.u)
    assert last == 10000
    for i, step in enumerate(recording.steps):
        t, q, u = states[int(step)]
        # Recordings round times to 1 ps (docs/recording.md); states are bit for bit.
        assert abs(t - recording.t[i]) <= 1e-12
        np.testing.assert_array_equal(q, recording.q[i])
        np.testing.assert_array_equal(u, recording.u[i])


def test_run_equals_the_command_line_with_its_summary(robbit, cli_run):
    recording, summary = cli_run
    trajectory = hopsim.Simulation(robbit).run()
    np.testing.assert_array_equal(trajectory.steps, recording.steps)
    np.testing.assert_array_equal(trajectory.t, recording.t)
    np.testing.assert_array_equal(trajectory.q, recording.q)
    np.testing.assert_array_equal(trajectory.u, recording.u)
    assert without_timing(trajectory.summary) == without_timing(summary)
    assert trajectory.events == recording.events
    assert summary["hops"] > 0  # the comparison covers flight and impacts


class MomentumImpulse:
    """Robbit's momentum-stored-impulse control (docs/physics.md §5.3) written in Python: motor
    torque `T` on the flywheel (`-T` on the disc) in stance; brake when the stored impulse
    `ζ = I_S I_R/(I_S + I_R) (ψ̇ - φ̇)` reaches `ζ0`; rearm at touchdown, or after
    `rearm_timeout` if the brake did not lift the disc."""

    def __init__(self, scene):
        c = scene.controller
        self.flywheel = c["flywheel"]
        self.disc = scene.bodies[self.flywheel]["parent"]
        i_s = scene.bodies[self.disc]["inertia"]
        i_r = scene.bodies[self.flywheel]["inertia"]
        self.reduced_inertia = i_s * i_r / (i_s + i_r)
        self.torque, self.limit = c["torque"], c["impulse_limit"]
        self.rearm_timeout, self.hold_brake = c["rearm_timeout"], c["hold_brake"]
        self.released_at = None
        self.airborne = False
        self.actuation = hopsim.Actuation()

    def __call__(self, sim):
        a = self.actuation
        a.clear()
        t, in_contact = sim.t, sim.in_contact
        if self.released_at is not None:
            touchdown = self.airborne and in_contact
            stalled = in_contact and t - self.released_at >= self.rearm_timeout
            if touchdown or stalled:
                self.released_at = None
            else:
                self.airborne = self.airborne or not in_contact
        if self.released_at is not None:
            if self.hold_brake:
                a.lock(self.disc, self.flywheel)
            return a
        w = sim.angular_velocities
        if self.reduced_inertia * (w[self.flywheel] - w[self.disc]) >= self.limit:
            a.brake(self.disc, self.flywheel)
            self.released_at, self.airborne = t, False
        else:
            a.torque(self.flywheel, self.torque, reaction=self.disc)
        return a


@pytest.mark.parametrize("hold_brake", [False, True])
def test_python_controller_reproduces_the_built_in_one(robbit, hold_brake):
    scene = robbit.with_overrides({"controller.hold_brake": hold_brake})
    builtin, python = hopsim.Simulation(scene), hopsim.Simulation(scene)
    controller = MomentumImpulse(scene)
    brakes = 0
    for _ in range(round(scene.duration / scene.dt)):
        builtin.step()
        python.step(actuation=controller(python))
        brakes += sum(e["kind"] == "brake" for e in python.events())
        assert python.events() == builtin.events()
        np.testing.assert_array_equal(python.q, builtin.q)
        np.testing.assert_array_equal(python.u, builtin.u)
    assert brakes >= 2 and python.hops >= 1


def test_state_arrays_are_copies(robbit):
    sim = hopsim.Simulation(robbit)
    q = sim.q
    q[1] = 5.0
    assert sim.q[1] == 0.1


def test_standing_contact_carries_the_weight(robbit):
    """Passive Robbit at rest on the ground: one stick contact whose normal percussion
    over a step is the weight times the step (m g Δt)."""
    sim = hopsim.Simulation(robbit)
    idle = hopsim.Actuation()
    sim.step(10, actuation=idle)
    [contact] = sim.contacts()
    mass = sum(b["mass"] for b in robbit.bodies)
    g = robbit.settings["gravity"]
    assert contact["contact"] == robbit.contacts[contact["index"]]
    assert contact["state"] == "stick"
    assert contact["gap"] <= 0.0
    assert contact["impulse_normal"] == pytest.approx(mass * g * robbit.dt, rel=1e-9)
    assert contact["impulse_tangent"] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(sim.u, 0.0, atol=1e-12)


def test_applied_impulse_lifts_the_robot(robbit):
    """An upward point impulse ζ at the centre of mass of a robot at rest: the contact
    opens and the centre of mass rises at ζ/m − g Δt (momentum balance over the step)."""
    sim = hopsim.Simulation(robbit)
    mass = sum(b["mass"] for b in robbit.bodies)
    zeta = 2.0
    kick = hopsim.Actuation()
    kick.point_impulse(0, (0.0, zeta))
    sim.step(actuation=kick)
    g, dt = robbit.settings["gravity"], robbit.dt
    assert sim.u[1] == pytest.approx(zeta / mass - g * dt, rel=1e-12)
    assert all(c["impulse_normal"] == 0.0 for c in sim.contacts())
    [event] = sim.events()
    assert event["kind"] == "applied_impulse" and event["magnitude"] == zeta


def test_joint_force_spins_the_flywheel(robbit):
    """A joint torque τ on the flywheel's joint for one step from rest: the flywheel, pivoted
    at its centre of mass, gains the angular velocity τ Δt / I_R whatever the disc does.
    The base has no joint to push on: refused."""
    sim = hopsim.Simulation(robbit)
    tau = 0.2
    a = hopsim.Actuation()
    a.joint_force(1, tau)
    sim.step(actuation=a)
    inertia = robbit.bodies[1]["inertia"]
    assert sim.angular_velocities[1] == pytest.approx(tau * robbit.dt / inertia, rel=1e-9)
    a.clear()
    a.joint_force(0, tau)
    with pytest.raises(ValueError):
        sim.step(actuation=a)


def test_actuation_naming_unknown_bodies_is_refused(robbit):
    sim = hopsim.Simulation(robbit)
    a = hopsim.Actuation()
    a.torque(7, 1.0)
    with pytest.raises(IndexError):
        sim.step(actuation=a)
    a.clear()
    a.lock(1, 1)
    with pytest.raises(ValueError):
        sim.step(actuation=a)
    a.clear()
    a.switch_shape(3, True)
    with pytest.raises(IndexError):
        sim.step(actuation=a)
    assert sim.step_count == 0


def test_run_arguments_are_checked(robbit):
    sim = hopsim.Simulation(robbit)
    with pytest.raises(ValueError):
        sim.run(duration=-1.0)
    with pytest.raises(ValueError):
        sim.run(record_rate=0.0)


def test_trajectory_to_pandas(robbit):
    pd = pytest.importorskip("pandas")
    trajectory = hopsim.Simulation(robbit).run(duration=0.1, record_rate=100.0)
    frame = trajectory.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == trajectory.columns
    assert frame["step"].dtype.kind == "i"
    assert len(frame) == len(trajectory) == 11
    np.testing.assert_array_equal(frame["y_m"], trajectory.q[:, 1])


def test_cradle_pair_contacts_carry_moreaus_simultaneous_percussions(robbit_path):
    """Newton's cradle, 3 balls of 1 kg, ε = 1 (docs/classics.md §1): ball 1 arrives at
    1 m/s on balls 2 and 3 at rest and touching. In the impact step both ball–ball contacts
    take part, and Moreau's law gives the velocities (−1/3, 2/3, 2/3) m/s: the percussions
    are m (1 + 1/3) = 4/3 N s between balls 1 and 2 and m 2/3 = 2/3 N s between 2 and 3."""
    scene = hopsim.Scene.load(robbit_path.parent / "classic" / "cradle-3.toml")
    sim = hopsim.Simulation(scene)
    idle = hopsim.Actuation()
    while not any(c["impulse_normal"] > 0.0 for c in sim.pair_contacts()):
        assert sim.t < 0.1, "no impact in the first 0.1 s"
        sim.step(actuation=idle)
    assert sim.contacts() == []
    contacts = sorted(sim.pair_contacts(), key=lambda c: c["impulse_normal"])
    assert [c["contact"] for c in contacts] == [
        f"{c['probe']}/{c['target']}" for c in contacts
    ]
    assert {(c["probe"], c["target"]) for c in contacts} <= {
        ("ball2", "ball1"), ("ball1", "ball2"), ("ball3", "ball2"), ("ball2", "ball3"),
    }
    assert {frozenset((c["probe"], c["target"])) for c in contacts} == {
        frozenset(("ball1", "ball2")), frozenset(("ball2", "ball3")),
    }
    # No gravity and no friction: the percussions are exact up to round-off.
    impulses = [c["impulse_normal"] for c in contacts]
    np.testing.assert_allclose(impulses, [2.0 / 3.0, 4.0 / 3.0], rtol=1e-9)
    for c in contacts:
        assert c["impulse_tangent"] == pytest.approx(0.0, abs=1e-12)
        assert abs(c["normal"][0]) == pytest.approx(1.0, abs=1e-12)
        assert c["gap"] <= 0.0
    np.testing.assert_allclose(sim.u[0::3], [-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0], atol=1e-9)


def test_body_arrays_follow_the_coordinates(robbit):
    """Robbit's disc is a floating base, so its centre of mass and angle are its coordinates
    `(x, y, φ)`; the flywheel pivots at that centre of mass with the absolute angle `ψ`:
    `body_positions`, `body_angles` and `angular_velocities` must say so at every step."""
    sim = hopsim.Simulation(robbit)
    for _ in range(3):
        sim.step(400)
        q, u = sim.q, sim.u
        p, angles = sim.body_positions, sim.body_angles
        assert p.shape == (2, 2)
        np.testing.assert_array_equal(p[0], q[:2])
        np.testing.assert_array_equal(p[1], p[0])
        np.testing.assert_array_equal(angles, q[2:4])
        np.testing.assert_array_equal(sim.angular_velocities, u[2:4])
    assert abs(sim.u[0]) > 0.0, "the disc should be moving"
