"""From Gymnasium's ``hopper.xml`` to a hopping controller in Python (docs/mjcf.md, "A worked
example").

The model file is read as it is (``hopsim.Scene.load``): MuJoCo's bodies, joints, motors
(gear 200, controls in [-1, 1]) and capsules, with hopsim's hard contact (no
penetration, Coulomb friction 0.9 and 2.0 from the geoms, restitution 0). The controller
is a three-phase state machine of the kind Raibert's hoppers use:

* stance, compressing (``u_z < 0``): hold a crouched pose, servo the torso's pitch with
  the hip;
* stance, extending: push off with constant controls on hip, knee and ankle;
* flight: swing the leg to a pose, the hip placing the foot by the forward speed's error.

Its twelve numbers are found by CMA-ES (``hopsim.optimize``) maximising the distance
covered in 4 s, with at least twelve flights longer than 80 ms asked for (a penalty per
missing flight) and a fall (torso below 0.7 m or pitched beyond 0.6 rad) ending the run.

    python examples/hopper_hopping.py                 # run PARAMS for 20 s, print the gait
    python examples/hopper_hopping.py --search        # search again (seed 1: ~10 s on 2 cores)

``hopper.xml`` is taken from the installed ``gymnasium`` package unless ``--model`` names it.
"""

import argparse
import os
import sys
import time

import numpy as np

import hopsim

#: Servo gains of the posture phases, per unit of control (the motors' gear is 200 N m).
KP, KD = 2.0, 0.1
#: A flight counts when no contact carries load for longer than this, s.
MIN_FLIGHT = 0.08
#: A fall: the torso's height below this (m; Hopper-v5's healthy bound) ...
MIN_HEIGHT = 0.7
#: ... or its pitch beyond this (rad).
MAX_PITCH = 0.6

#: The search space: pose targets (rad), push-off controls (in [-1, 1]), gains.
BOUNDS = {
    "thigh_c": (-1.0, 0.0), "leg_c": (-1.0, 0.0), "foot_c": (-0.7, 0.7), "k_pitch": (-3.0, 3.0),
    "thigh_t": (-1.0, 1.0), "leg_t": (-1.0, 1.0), "foot_t": (-1.0, 1.0),
    "thigh_f": (-1.0, 0.0), "leg_f": (-1.5, 0.0), "foot_f": (-0.7, 0.7),
    "k_v": (-1.0, 1.0), "v": (0.0, 2.0),
}  # fmt: skip

#: What ``--search`` (seed 1, population 16, 40 generations) found.
PARAMS = {
    "thigh_c": -0.15316095919505912, "leg_c": -0.000597584561281117,
    "foot_c": 0.4028616872125943, "k_pitch": -0.43372810316478017,
    "thigh_t": 0.6651650298990059, "leg_t": -0.30559766253576903,
    "foot_t": -0.3083076766859354, "thigh_f": -0.0813188423610236,
    "leg_f": -0.7716250235223109, "foot_f": 0.6411274306798727,
    "k_v": 0.5545859234630381, "v": 0.5453271208503807,
}  # fmt: skip


def hopper_xml():
    """The path of Gymnasium's ``hopper.xml``."""
    import gymnasium

    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "hopper.xml")


class HoppingController:
    """The three-phase controller; ``q = [rootx, rootz, rooty, thigh, leg, foot]`` as MuJoCo's
    ``qpos`` (hopsim's coordinates of an imported model are MuJoCo's)."""

    def __init__(self, p):
        self.p = p

    def __call__(self, sim):
        q, u, p = sim.q, sim.u, self.p
        if sim.in_contact and u[1] < 0.0:
            target = np.array([p["thigh_c"] + p["k_pitch"] * q[2], p["leg_c"], p["foot_c"]])
            control = KP * (target - q[3:]) - KD * u[3:]
        elif sim.in_contact:
            control = np.array([p["thigh_t"] + p["k_pitch"] * q[2], p["leg_t"], p["foot_t"]])
        else:
            target = np.array([p["thigh_f"] - p["k_v"] * (u[0] - p["v"]), p["leg_f"], p["foot_f"]])
            control = KP * (target - q[3:]) - KD * u[3:]
        sim.control = np.clip(control, -1.0, 1.0)


def rollout(scene, p, duration=4.0):
    """Runs the controller ``p`` for ``duration`` s; returns the gait's figures:
    ``distance`` (m), ``flights`` (longer than MIN_FLIGHT), ``hops`` (the simulation's
    count), ``fell_at`` (s, or None) and ``sim``."""
    sim = hopsim.Simulation(scene)
    controller = HoppingController(p)
    min_flight_steps = round(MIN_FLIGHT / scene.dt)
    airborne, flights, fell_at = 0, 0, None
    for _ in range(round(duration / scene.dt)):
        controller(sim)
        sim.step()
        if sim.q[1] < MIN_HEIGHT or abs(sim.q[2]) > MAX_PITCH:
            fell_at = sim.t
            break
        if not sim.in_contact:
            airborne += 1
        else:
            flights += airborne > min_flight_steps
            airborne = 0.0
    return {"distance": sim.q[0], "flights": flights, "hops": sim.hops, "fell_at": fell_at, "sim": sim}


def objective(scene, duration=4.0, flights_asked=12):
    """The search's objective: the distance, less 0.2 m per missing flight and 2 m per
    second lost to a fall."""

    def value(p):
        g = rollout(scene, p, duration)
        lost = duration - g["fell_at"] if g["fell_at"] is not None else 0.0
        return g["distance"] - 0.2 * max(flights_asked - g["flights"], 0) - 2.0 * lost

    return value


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", help="the MJCF file (default: gymnasium's hopper.xml)")
    ap.add_argument("--search", action="store_true", help="find the controller with CMA-ES")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--generations", type=int, default=40)
    ap.add_argument("--duration", type=float, default=20.0, help="the run shown at the end, s")
    args = ap.parse_args(argv)
    scene = hopsim.Scene.load(args.model or hopper_xml())
    params = PARAMS
    if args.search:
        start = time.time()
        result = hopsim.optimize(objective(scene), BOUNDS, maximize=True, population=16,
                                 generations=args.generations, seed=args.seed)
        print(f"search: {result} in {time.time() - start:.1f} s")
        params = result.best
    g = rollout(scene, params, args.duration)
    t = g["fell_at"] or args.duration
    print(f"{args.duration:g} s: {g['distance']:.2f} m forward ({g['distance'] / t:.2f} m/s), "
          f"{g['hops']} hops, {g['flights']} flights > {MIN_FLIGHT * 1e3:.0f} ms, "
          + (f"fell at {g['fell_at']:.2f} s" if g["fell_at"] is not None else "no fall"))
    return g


if __name__ == "__main__":
    main(sys.argv[1:])
