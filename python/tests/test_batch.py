"""hopsim.Batch: copies of a scene stepped together on Rust threads. Copy i equals a
single hopsim.Simulation with the same start and controls bit for bit at 1, 2 and 4
threads; a copy that fails stops alone; arrays have their shapes and dtypes and are
filled in place; reset and set_state restart one copy."""

import numpy as np
import pytest

import hopsim

N = 64
MOTOR = '\n[[actuators]]\nname = "motor"\njoint = "flywheel"\nkind = "motor"\n'


@pytest.fixture(scope="module")
def robbit_motor(robbit_path) -> hopsim.Scene:
    """Robbit (its momentum-stored impulse controller) with a motor on the flywheel."""
    return hopsim.Scene.from_toml(robbit_path.read_text() + MOTOR, path=str(robbit_path))


def start(scene, i):
    """Copy i's start: standing at x = i cm, sliding and spinning by amounts of its own."""
    q = np.array([0.0, 0.1, 0.0, 0.0])  # the scene's [initial]: standing
    q[0] = 0.01 * i
    u = np.zeros(4)
    u[0] = 0.02 * (i - 32)
    u[3] = 0.5 * (i % 7)
    return q, u


def control(i, b):
    return 0.05 * (((i * 13 + b * 7) % 11) - 5)


@pytest.mark.parametrize("threads", [1, 2, 4])
def test_copies_equal_single_simulations_bit_for_bit(robbit_motor, threads):
    batch = hopsim.Batch(robbit_motor, N, threads=threads)
    assert batch.threads == threads and len(batch) == N
    singles = [hopsim.Simulation(robbit_motor) for _ in range(N)]
    for i, sim in enumerate(singles):
        q, u = start(robbit_motor, i)
        batch.set_state(i, q, u)
        sim.set_state(q, u)
    q_view, contact_view = batch.q, batch.in_contact
    touched = 0
    for b in range(40):
        controls = np.array([[control(i, b)] for i in range(N)])
        batch.step(50, controls=controls)
        for i, sim in enumerate(singles):
            sim.control = [control(i, b)]
            sim.step(50)
            assert batch.t[i] == sim.t
            assert np.array_equal(batch.q[i], sim.q), (i, b)
            assert np.array_equal(batch.u[i], sim.u), (i, b)
            assert batch.in_contact[i] == sim.in_contact
            touched += sim.in_contact
        assert not batch.done.any()
    # The arrays are filled in place: the views taken at the start see the last step.
    assert q_view is batch.q and np.array_equal(q_view[5], singles[5].q)
    assert contact_view is batch.in_contact
    # The copies did different things.
    assert 0 < touched < 40 * N
    assert not np.array_equal(batch.q[0], batch.q[1])


def test_shapes_dtypes_and_read_only_states(robbit_motor):
    batch = hopsim.Batch(robbit_motor, 3, threads=1)
    for name, shape, dtype in [
        ("t", (3,), np.float64),
        ("q", (3, 4), np.float64),
        ("u", (3, 4), np.float64),
        ("controls", (3, 1), np.float64),
        ("in_contact", (3,), np.bool_),
        ("done", (3,), np.bool_),
    ]:
        array = getattr(batch, name)
        assert array.shape == shape and array.dtype == dtype, name
    assert np.array_equal(batch.q, np.tile([0.0, 0.1, 0.0, 0.0], (3, 1)))
    assert batch.in_contact.all(), "Robbit starts standing"
    with pytest.raises(ValueError):
        batch.q[0, 0] = 1.0
    with pytest.raises(ValueError):
        batch.done[0] = True
    batch.controls[1, 0] = 0.2  # written in place
    batch.step()
    assert batch.controls[1, 0] == 0.2 and batch.t[0] == robbit_motor.dt
    with pytest.raises(ValueError, match=r"expected shape \[3, 1\]"):
        batch.controls = np.zeros((3, 2))
    with pytest.raises(IndexError, match="copy 3 is out of range"):
        batch.reset(3)
    with pytest.raises(ValueError, match="copy 1"):
        batch.set_state(1, [0.0, 0.05, 0.0, 0.0], np.zeros(4))  # inside the ground


def test_a_failing_copy_stops_alone_and_resets(robbit_motor):
    batch = hopsim.Batch(robbit_motor, 8, threads=2)
    single = hopsim.Simulation(robbit_motor)
    controls = np.full((8, 1), 0.1)
    controls[3] = np.nan
    single.control = [0.1]
    batch.step(200, controls=controls)
    single.step(200)
    assert list(np.flatnonzero(batch.done)) == [3]
    assert "finite" in batch.error(3), batch.error(3)
    assert batch.t[3] == 0.0
    for i in [0, 1, 2, 4, 5, 6, 7]:
        assert batch.error(i) is None
        assert np.array_equal(batch.q[i], single.q)
    batch.reset(3)
    assert not batch.done[3] and batch.error(3) is None
    assert np.array_equal(batch.q[3], [0.0, 0.1, 0.0, 0.0])
    batch.reset()
    assert (batch.t == 0.0).all()


def test_a_model_makes_a_batch():
    model = hopsim.Model()
    model.simulation(duration=1.0, dt=1e-3)
    model.body("ball", mass=1.0, inertia=0.1)
    model.shape("ball", body="ball", type="circle", radius=0.1)
    model.initial(q=[0.0, 1.0, 0.0], u=[0.0, 0.0, 0.0])
    batch = hopsim.Batch(model, 2, threads=1)
    batch.step(100)
    # Free fall for 0.1 s: y = 1 - g t²/2 to round-off (the midpoint rule is exact here).
    assert batch.q[:, 1] == pytest.approx(1.0 - 0.5 * 9.81 * 0.1**2, abs=1e-12)


def test_copies_with_their_own_overrides_equal_simulations_of_their_scenes(robbit_motor):
    """Domain randomisation: each copy its own friction, restitution and controller torque;
    copy i equals a simulation of the scene with copy i's overrides, bit for bit."""
    overrides = [
        {"environment.friction": 0.4 + 0.1 * i, "controller.torque": 0.02 * (i + 1),
         "environment.restitution": 0.05 * (i % 3)}
        for i in range(6)
    ]
    batch = hopsim.Batch(robbit_motor, 6, threads=2, overrides=overrides)
    singles = [hopsim.Simulation(robbit_motor.with_overrides(o)) for o in overrides]
    for _ in range(20):
        batch.step(100)
        for i, sim in enumerate(singles):
            sim.step(100)
            assert np.array_equal(batch.q[i], sim.q), i
            assert np.array_equal(batch.u[i], sim.u), i
    # Different parameters, different motions.
    assert len({tuple(q) for q in batch.q}) == 6
    with pytest.raises(ValueError, match="2 sets of overrides for 6 copies"):
        hopsim.Batch(robbit_motor, 6, overrides=overrides[:2])
