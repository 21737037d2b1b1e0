"""The symmetric five-bar leg hopper stepped from Python (docs/classics.md §8).

The hopper of ``scenes/classic/five-bar-hopper-forward.toml`` is built in code with
``hopsim.Model``: a torso that travels level in x and y, two thighs on one hip axis, two
shins pinned together at the foot by a revolute loop joint (``Model.loop``), and a
position servo in each hip (``Model.actuator``, without a control signal). Python computes
the hips' set points at each step's midpoint time,

    hip_l = -pi/2 - a0 - A sin(wt) + B sin(wt + pi/4)
    hip_r = -pi/2 + a0 + A sin(wt) + B sin(wt + pi/4),

A sets the leg's thrust and B its sweep: B = 0.1 rad hops forward, B = 0 in place. Run:

    python examples/five_bar_hopper.py [--duration 20] [--sweep 0.1]

It prints the hops, the distance and mean speed, the largest loop error (the distance of
the shins' ends), and the energy balance; the run is strict (an LCP without a certified
solution stops it with an error), and it exits with 1 if the hopper did not hop (fewer
than one hop a second) or its loop opened beyond 1e-10 m.
"""

import argparse
import math
import sys

import hopsim

THIGH, SHIN = 0.1, 0.2  # m
FREQUENCY = 5.0  # Hz
SPREAD, THRUST, SWEEP_PHASE = math.radians(30.0), 0.3, math.pi / 4


def hopper(duration: float) -> hopsim.Model:
    """The forward hopper's model, its hips servoed to set points from Python."""
    model = (
        hopsim.Model("five-bar hopper from Python")
        .simulation(duration=duration, dt=1e-4, record_rate=500, strict=True)
        .environment(friction=1.0, restitution=0.0)
        .body("guide", base="fixed")
        .body("carriage", parent="guide", joint="prismatic", axis=[1.0, 0.0],
              coordinate_name="x", mass=0.0, inertia=0.0)
        .body("torso", parent="carriage", joint="prismatic", axis=[0.0, 1.0],
              coordinate_name="h", mass=1.0, inertia=0.01)
    )
    for side in ("l", "r"):
        model = (
            model.body(f"thigh_{side}", parent="torso", com=[THIGH / 2, 0.0],
                       coordinate_name=f"hip_{side}", mass=0.05, inertia=4.2e-5)
            .body(f"shin_{side}", parent=f"thigh_{side}", pivot=[THIGH / 2, 0.0],
                  com=[SHIN / 2, 0.0], coordinate_name=f"knee_{side}", mass=0.05,
                  inertia=1.7e-4)
            .actuator(f"hip_{side}", joint=f"thigh_{side}", kind="position", kp=20.0, kv=0.2)
        )
    # The foot: the shins' ends pinned together (a revolute loop joint), a point on shin_l.
    model = (
        model.shape("foot", body="shin_l", type="point", position=[SHIN / 2, 0.0])
        .shape("trunk", body="torso", type="box", half_width=0.05, half_height=0.03)
        .loop("foot", type="revolute", body_a="shin_l", point_a=[SHIN / 2, 0.0],
              body_b="shin_r", point_b=[SHIN / 2, 0.0])
    )
    # The start: thighs at -120° and -60°, the foot below the hip 2 cm above the ground.
    hip_l, hip_r = -math.pi / 2 - SPREAD, -math.pi / 2 + SPREAD
    foot_depth = THIGH * math.cos(SPREAD) + math.sqrt(SHIN**2 - (THIGH * math.sin(SPREAD)) ** 2)
    # The knee angles (relative to the thighs) that put both shins' ends on the vertical
    # below the hip, at foot_depth.
    def knee_angle(hip: float) -> float:
        thigh_end = (THIGH * math.cos(hip), THIGH * math.sin(hip))
        shin = math.atan2(-foot_depth - thigh_end[1], -thigh_end[0])
        return shin - hip
    return model.initial(q=[0.0, foot_depth + 0.02, hip_l, knee_angle(hip_l),
                            hip_r, knee_angle(hip_r)])


def foot_gap(sim: hopsim.Simulation, shins: list) -> float:
    """The distance between the two shins' ends: the foot loop's error, m."""
    positions, angles = sim.body_positions, sim.body_angles
    ends = [(positions[b][0] + SHIN / 2 * math.cos(angles[b]),
             positions[b][1] + SHIN / 2 * math.sin(angles[b])) for b in shins]
    return math.dist(*ends)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=20.0, help="s (20)")
    parser.add_argument("--sweep", type=float, default=0.1, help="B, rad (0.1; 0: in place)")
    args = parser.parse_args()
    scene = hopper(args.duration).scene()
    sim = hopsim.Simulation(scene)
    dt, omega = scene.dt, 2 * math.pi * FREQUENCY
    steps = round(args.duration / dt)
    shins = [scene.body_index(f"shin_{side}") for side in ("l", "r")]
    loop_error = 0.0
    for k in range(steps):
        t = (k + 0.5) * dt  # the step's midpoint time, as the scene's control signals
        thrust = THRUST * math.sin(omega * t)
        sweep = args.sweep * math.sin(omega * t + SWEEP_PHASE)
        sim.control = [-math.pi / 2 - SPREAD - thrust + sweep,
                       -math.pi / 2 + SPREAD + thrust + sweep]
        sim.step()
        if k % 10 == 0:
            loop_error = max(loop_error, foot_gap(sim, shins))
    x = sim.q[0]
    energy = sim.energy()
    print(f"{sim.hops} hops in {sim.t:.1f} s, {x:.3f} m ({x / sim.t:.3f} m/s)")
    print(f"largest loop error {loop_error:.2e} m (every 10th step); no LCP failure (strict)")
    print(f"energy: actuator work {energy['actuator_work']:.3f} J, "
          f"balance error {energy['balance_error']:.2e} J")
    ok = sim.hops >= sim.t and loop_error <= 1e-10
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
