"""How a CaneBot hops: each flight classified by the thesis' cases (docs/physics.md §5.4,
docs/canebot.md "The mechanism"), and the cane extensions the ground held back.

* **pole vault** (case c): the cane is the last contact before take-off (the body
  rotated about the cane tip into the flight);
* **foot** (cases a and b): the foot's arc is the last contact; the foot's mean angular
  velocity in the flight is printed (a strong backward rotation is (b), a slight one (a));
* **blocked**: the thesis' trigger asked for the cane but its tip was in the ground, so the
  extension waited: the controller's rule (the tip's gap above the flat ground > 0)
  replayed from the state at the start of each step.

    python examples/canebot_mechanism.py scenes/canebot-identified.toml
    python examples/canebot_mechanism.py scenes/canebot-identified.toml --set controller.cane_mode=extended

Prints each held-back extension and each flight, then the counts; ``--json`` writes them
for a test or a notebook. Flat terrain only (the tip's gap is its height).
"""

import argparse
import json
import math
import sys

import numpy as np

import hopsim

#: Flights shorter than this are bounces and left out here (s). The run summary's `hops`
#: counts every flight that clears the ground by 1 mm (docs/physics.md), bounces included.
MIN_FLIGHT = 0.02


def built(scene):
    """The cane tip in the foot's frame (m) and the controller's keys, as the scene (with
    its overrides) builds them."""
    import tomllib

    spec = tomllib.loads(scene.model.toml())
    cane = next(s for s in spec["shapes"] if s["name"] == "cane")
    return np.array(cane["position"], dtype=float), spec["controller"]


def analyse(scene):
    """Steps ``scene`` once through and returns its flights and, for each motor period
    whose cane window the thesis' trigger opens (docs/physics.md §5.4; CD + CDC < 1), how
    long the ground held the extension back (s)."""
    sim = hopsim.Simulation(scene)
    shapes = scene.shapes
    foot, cane = shapes.index("foot"), shapes.index("cane")
    lower = scene.body_index("lower")
    tip, c = built(scene)
    period = 1.0 / c["frequency"]
    timed = c.get("cane_mode") == "timed" and c["cane_delay"] + c["cane_duration"] < 1.0
    flights, held = [], {}
    airborne, last_shape, start = False, None, None
    while sim.t < scene.duration - 0.5 * scene.dt:
        # The controller decides at the start of a step, from the state before it.
        t0 = sim.t
        p, phi = sim.body_positions[lower], float(sim.body_angles[lower])
        tip_height = p[1] + math.sin(phi) * tip[0] + math.cos(phi) * tip[1]
        phase = t0 / period - math.floor(t0 / period)
        if timed and c["cane_delay"] <= phase < c["cane_delay"] + c["cane_duration"]:
            k = math.floor(t0 / period)
            waited, out = held.get(k, (0.0, False))
            if not out:  # not out yet in this window: the controller's rule, gap > 0
                out = bool(tip_height > 0.0)
                held[k] = (waited + (0.0 if out else scene.dt), out)
        sim.step(1)
        t = sim.t
        touching = sim.shape_in_contact()
        x = float(sim.body_positions[lower, 0])
        phi = float(sim.body_angles[lower])
        if touching[cane] or touching[foot]:
            if airborne and t - start[0] >= MIN_FLIGHT:
                flights.append({
                    "take_off_s": start[0],
                    "duration_s": t - start[0],
                    "from": start[3],
                    "length_m": x - start[1],
                    "rotation_rad_per_s": (phi - start[2]) / (t - start[0]),
                })
            airborne = False
            last_shape = "cane" if touching[cane] else "foot"
        elif not airborne:
            airborne, start = True, (t, x, phi, last_shape)
    return flights, {k: v[0] for k, v in held.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--json", help="write the flights and counts here")
    args = parser.parse_args()
    overrides = dict(s.split("=", 1) for s in args.set)
    scene = hopsim.Scene.load(args.scene, overrides=overrides)
    flights, held = analyse(scene)
    rotations = np.array([f["rotation_rad_per_s"] for f in flights]) if flights else np.zeros(0)
    # Backward rotation is positive phi rate (nose up, counter-clockwise) for a robot
    # walking towards +x.
    for k, h in sorted(held.items()):
        if h > 0.0:
            print(f"period {k:2d}: the cane's extension held back {1000 * h:5.1f} ms (tip in the ground)")
    for f in flights:
        print(f"t = {f['take_off_s']:6.3f} s  from {f['from'] or '-':4s}  flight {1000 * f['duration_s']:5.1f} ms"
              f"  length {100 * f['length_m']:6.2f} cm  foot rotation {f['rotation_rad_per_s']:+6.2f} rad/s")
    counts = {
        "flights": len(flights),
        "from_cane": sum(f["from"] == "cane" for f in flights),
        "from_foot": sum(f["from"] == "foot" for f in flights),
        "mean_length_from_cane_m": float(np.mean([f["length_m"] for f in flights if f["from"] == "cane"]))
        if any(f["from"] == "cane" for f in flights) else math.nan,
        "mean_length_from_foot_m": float(np.mean([f["length_m"] for f in flights if f["from"] == "foot"]))
        if any(f["from"] == "foot" for f in flights) else math.nan,
        "mean_rotation_rad_per_s": float(rotations.mean()) if len(rotations) else math.nan,
        "cane_windows": len(held),
        "cane_windows_held_back": sum(h > 0.0 for h in held.values()),
        "cane_held_back_s": sum(held.values()),
    }
    print(json.dumps(counts, indent=2))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as out:
            json.dump({"flights": flights, "counts": counts}, out, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
