"""Searches for a CaneBot in which the thesis' timed cane wins (docs/canebot.md,
"Searching for the thesis' cane effect"): CMA-ES (hopsim.optimize) over the lost design
parameters within plausible bounds, on a Dask LocalCluster.

Two objectives:

* ``gain`` (the first search): the distance per hop of the cane triggered at CD = 0.1,
  CDC = 0.5 (the thesis' schedule) over the better of the two permanent cases; three runs
  per point. It rewards hop-count artefacts (docs/canebot.md).
* ``targets``: a score of the thesis' findings (docs/physics.md §5.4), staged so that most
  points cost three runs: retracted period 1, extended period 2 and not faster, the timed
  cane at 0.1 / 0.5 ahead in distance per hop *and* in speed; only then the Figure 6.5
  sweeps (CDC = 0.5 and CDC = 1 over CD), scored on how many CDC = 0.5 points beat both
  permanent cases, where the peak lies, how many CDC = 1 points stay below, and how far
  the peak is from 8.4 cm.
* ``robust``: the ``targets`` score averaged over the design and four designs within ±1 %
  of it (a pattern that a robot built to tolerances keeps); five times the cost.

``--start best.json --sigma 0.1`` starts at a design with a small step;
``--robustness N`` scores N designs within ±1 % of ``OUT/best.json``'s and stops.

    python examples/canebot_identify.py --objective targets --population 16 --generations 60 \
        --out out/canebot-targets

The search is saved after every generation (OUT/search.json) and resumed from it when run
again.
"""

import argparse
import json
import os
import random
from pathlib import Path

import hopsim

REPO = Path(__file__).resolve().parents[1]

#: The searched keys and their bounds of the ``gain`` search (docs/canebot.md gives the
#: reasons).
PARAMS = {
    "springs.front.stiffness": (60.0, 400.0),   # N/m, each of the two extension springs
    "springs.rear.stiffness": (60.0, 400.0),
    "bodies.upper.damping": (0.005, 0.1),       # N m s/rad, a small gearbox
    "environment.friction": (0.3, 0.9),         # plywood on wood to rubber on wood
    "environment.restitution": (0.0, 0.3),      # plywood foot, wooden floor
    "shapes.cane.position.0": (0.12, 0.20),     # m, cane tip in the foot frame
    "shapes.cane.position.1": (-0.06, 0.0),
    "bodies.upper.mass": (0.2, 0.45),           # kg: battery, electronics, servo
}


#: The ``targets`` search: the keys above but the cane's position, plus the links' masses and
#: inertias, the joint's height, the foot's arc and the cane's place on it, within the bounds
#: of a robot about 0.34 m long built from the thesis' parts. The foot is given by its length
#: (the arc's chord, at most the robot's length) and radius; the cane by how far its tip
#: protrudes radially beyond the arc and its angle from the arc's front end (negative:
#: behind it): it stays at the foot's front tip. ``design`` turns them into scene keys.
TARGET_PARAMS = {
    **{k: v for k, v in PARAMS.items() if not k.startswith("shapes.cane.")},
    "bodies.lower.mass": (0.3, 0.55),           # kg: plywood foot, 70 W flat motor, gearbox
    "bodies.lower.inertia": (1.5e-3, 5e-3),     # kg m²
    "bodies.upper.inertia": (1.2e-3, 4e-3),     # kg m²: a 0.25–0.35 m bar
    "bodies.upper.pivot.1": (0.06, 0.14),       # m, the joint above the foot's centre of mass
    "foot_radius": (0.18, 0.5),                 # m, the arc's radius
    "foot_length": (0.20, 0.34),                # m, the arc's chord: the foot's length
    "cane_protrusion": (0.005, 0.04),           # m, the cane tip beyond the arc, radially
    "cane_angle": (-0.15, 0.05),                # rad, the cane's angle from the arc's front end
}

#: The foot's lowest point below its centre of mass, m (as scenes/canebot-timed.toml).
FOOT_DROP = 0.04
#: The thesis' reading of Figure 6.5 (docs/physics.md §5.4): the peak, m per hop.
THESIS_PEAK = 0.084
#: The Figure 6.5 sweeps: CD at CDC = 0.5 (0.1 is stage A's run) and at CDC = 1.
SWEEP_HALF = (0.0, 0.05, 0.15, 0.2, 0.3, 0.4, 0.5)
SWEEP_FULL = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)


def design(values):
    """Scene overrides of a point: the scene keys as they are; the foot's radius and length
    as the arc's centre, radius and end angles (the lowest point kept FOOT_DROP below the
    centre of mass); the cane's protrusion and angle as its tip's position."""
    import math

    derived = ("foot_", "cane_")
    out = {k: v for k, v in values.items() if not k.startswith(derived)}
    if "foot_radius" in values:
        r = values["foot_radius"]
        e = math.asin(min(1.0, values["foot_length"] / (2.0 * r)))
        cy = r - FOOT_DROP
        out.update({
            "shapes.foot.radius": r,
            "shapes.foot.center.1": cy,
            "shapes.foot.start": -math.pi / 2 - e,
            "shapes.foot.end": -math.pi / 2 + e,
        })
        if "cane_protrusion" in values:
            a = -math.pi / 2 + e + values["cane_angle"]
            d = r + values["cane_protrusion"]
            out["shapes.cane.position.0"] = d * math.cos(a)
            out["shapes.cane.position.1"] = cy + d * math.sin(a)
    return out


def scene():
    return hopsim.Scene.load(
        REPO / "scenes" / "canebot-timed.toml",
        overrides={"controller.cane_schedule": "thesis"},
    )


def summaries(base, values):
    """The timed, retracted and extended runs of the design `values`."""
    timed = base.with_overrides(values)
    out = {}
    for name, mode in [("timed", {}), ("retracted", {"controller.cane_mode": "retracted"}),
                       ("extended", {"controller.cane_mode": "extended"})]:
        s = timed.with_overrides(mode) if mode else timed
        out[name] = hopsim.Simulation(s).run(frames=False).summary
    return out


def gain(values):
    """Distance per hop of the timed cane over the better permanent case; rejected when a
    case hops fewer than 10 times in 10 s."""
    runs = summaries(scene(), values)
    for name, s in runs.items():
        if s["hops"] < 10:
            raise ValueError(f"{name}: {s['hops']} hops")
    per_hop = {k: s["distance_per_hop_m"] for k, s in runs.items()}
    return per_hop["timed"] / max(per_hop["retracted"], per_hop["extended"])


def run(base, overrides):
    return hopsim.Simulation(base.with_overrides(overrides)).run(frames=False).summary


def targets(values):
    """The score of the thesis' findings (see the module doc); rejected when a case hops
    fewer than 10 times in 10 s. Stage A (three runs) scores up to 2; stage B adds up to 3."""
    base = scene().with_overrides(design(values))
    runs = {
        "timed": run(base, {}),
        "retracted": run(base, {"controller.cane_mode": "retracted"}),
        "extended": run(base, {"controller.cane_mode": "extended"}),
    }
    for name, s in runs.items():
        if s["hops"] < 10:
            raise ValueError(f"{name}: {s['hops']} hops")
    h = {k: s["distance_per_hop_m"] for k, s in runs.items()}
    v = {k: s["mean_speed_mps"] for k, s in runs.items()}
    period = {k: (s.get("gait") or {}).get("period") for k, s in runs.items()}
    best_permanent = max(h["retracted"], h["extended"])
    gain = h["timed"] / best_permanent
    speed = v["timed"] / v["retracted"] if v["retracted"] > 0 else 0.0
    periods_met = (period["retracted"] == 1) + (period["extended"] == 2 and v["extended"] <= v["retracted"])
    # Stage A: the periods, then the timed cane ahead in distance per hop and in speed.
    score = 0.5 * periods_met + 0.5 * min(gain, 1.3) / 1.3 + 0.5 * min(speed, 1.3) / 1.3
    if periods_met < 2 or gain < 1.2 or speed < 1.0:
        return score
    # Stage B: Figure 6.5.
    half = {0.1: h["timed"]}
    for cd in SWEEP_HALF:
        half[cd] = run(base, {"controller.cane_delay": cd})["distance_per_hop_m"]
    full = [run(base, {"controller.cane_delay": cd, "controller.cane_duration": 1.0})["distance_per_hop_m"]
            for cd in SWEEP_FULL]
    peak_cd = max(half, key=half.get)
    above = sum(x >= 1.3 * best_permanent for x in half.values()) / len(half)
    below = sum(x < best_permanent for x in full) / len(full)
    closeness = max(0.0, 1.0 - abs(half[peak_cd] - THESIS_PEAK) / THESIS_PEAK)
    return score + above + below + 0.5 * (0.05 <= peak_cd <= 0.2) + 0.5 * closeness


#: The tolerance of a built robot: every key within ±1 % of its design value.
TOLERANCE = 0.01
#: The same four relative offsets for every design (common random numbers), so that the
#: ``robust`` objective is a deterministic function of the design.
def offsets(rng, keys):
    """One relative offset in [-1, 1] per key, drawn from ``rng`` in the keys' sorted order."""
    return {key: rng.uniform(-1.0, 1.0) for key in sorted(keys)}


OFFSETS = [offsets(random.Random(1000 + i), TARGET_PARAMS) for i in range(4)]


def moved(values, offsets, params=TARGET_PARAMS, spread=TOLERANCE):
    """``values`` with each key moved by ``spread`` times its offset in [-1, 1], within bounds."""
    return {k: min(params[k][1], max(params[k][0], v * (1.0 + spread * offsets[k])))
            for k, v in values.items()}


def robust(values):
    """The ``targets`` score averaged over the design and four designs within ±1 % of it
    (``OFFSETS``; a rejected one scores 0): a design whose pattern a built robot keeps."""
    scores = []
    for point in [values] + [moved(values, o) for o in OFFSETS]:
        try:
            scores.append(targets(point))
        except ValueError:
            scores.append(0.0)
    return sum(scores) / len(scores)


OBJECTIVES = {
    "gain": (gain, PARAMS),
    "targets": (targets, TARGET_PARAMS),
    "robust": (robust, TARGET_PARAMS),
}


def robustness(values, params, objective, samples, spread=0.01, seed=0):
    """The objective of ``samples`` designs around ``values``, each key moved by a uniform
    relative ``spread`` (kept within its bounds): how much of the score survives the
    tolerances of a built robot. Rejected designs score None."""
    rng = random.Random(seed)
    scores = []
    for _ in range(samples):
        try:
            scores.append(objective(moved(values, offsets(rng, params), params, spread)))
        except ValueError:
            scores.append(None)
    return scores


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", type=int, default=12)
    parser.add_argument("--generations", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", default="out/canebot-identify")
    parser.add_argument("--objective", choices=sorted(OBJECTIVES), default="gain")
    parser.add_argument("--start", metavar="JSON",
                        help="start the search at the design `best` of this file (a best.json)")
    parser.add_argument("--sigma", type=float, default=0.3,
                        help="CMA-ES's initial step, a fraction of each key's range")
    parser.add_argument("--robustness", type=int, metavar="N",
                        help="score N designs within ±1 %% of OUT/best.json's and stop")
    args = parser.parse_args()
    objective, params = OBJECTIVES[args.objective]
    if args.robustness:
        with open(os.path.join(args.out, "best.json"), encoding="utf-8") as f:
            best = json.load(f)["best"]
        scores = robustness(best, params, objective, args.robustness)
        kept = sorted(x for x in scores if x is not None)
        print(f"best {objective(best):.3f}; {args.robustness} designs within ±1 %: "
              f"{len(kept)} scored, median {kept[len(kept) // 2] if kept else float('nan'):.3f}, "
              f"min {kept[0] if kept else float('nan'):.3f}, max {kept[-1] if kept else float('nan'):.3f}")
        print(" ".join("rejected" if x is None else f"{x:.2f}" for x in scores))
        return
    from distributed import Client, LocalCluster

    start = None
    if args.start:
        with open(args.start, encoding="utf-8") as f:
            start = json.load(f)["best"]

    os.makedirs(args.out, exist_ok=True)
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        result = hopsim.optimize(
            objective, params, maximize=True, population=args.population,
            generations=args.generations, seed=args.seed, client=client, start=start,
            sigma=args.sigma,
            checkpoint=os.path.join(args.out, "search.json"), out=args.out, name=args.objective,
        )
    print(result.text)
    best = summaries(scene(), design(result.best))
    report = {
        "best": result.best,
        "overrides": design(result.best),
        args.objective: result.value,
        "evaluations": len(result.evaluations),
        "rejected": result.rejected,
        "cases": {
            k: {"distance_per_hop_m": s["distance_per_hop_m"], "hops": s["hops"],
                "mean_speed_mps": s["mean_speed_mps"],
                "gait_period": (s.get("gait") or {}).get("period")}
            for k, s in best.items()
        },
    }
    with open(os.path.join(args.out, "best.json"), "w", encoding="utf-8") as f:
        json.dump(report, f, indent=2)
    print(json.dumps(report["cases"], indent=2))


if __name__ == "__main__":
    main()
