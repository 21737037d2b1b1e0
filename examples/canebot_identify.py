"""A first search for a CaneBot in which the thesis' timed cane wins (docs/canebot.md,
"Searching for the thesis' cane effect"): CMA-ES (hopsim.optimize) over spring, damping,
contact, cane and mass parameters within plausible bounds, maximising the distance per hop
of the cane triggered at CD = 0.1, CDC = 0.5 (the thesis' schedule) over the better of the
two permanent cases, on a Dask LocalCluster.

    python examples/canebot_identify.py --population 12 --generations 20 --out out/canebot-identify

Each point costs three 10 s runs (timed, retracted, extended). The search is saved after
every generation (OUT/search.json) and resumed from it when run again.
"""

import argparse
import json
import os
from pathlib import Path

import hopsim

REPO = Path(__file__).resolve().parents[1]

#: The searched keys and their bounds (docs/canebot.md gives the reasons).
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", type=int, default=12)
    parser.add_argument("--generations", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", default="out/canebot-identify")
    args = parser.parse_args()
    from distributed import Client, LocalCluster

    os.makedirs(args.out, exist_ok=True)
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        result = hopsim.optimize(
            gain, PARAMS, maximize=True, population=args.population,
            generations=args.generations, seed=args.seed, client=client,
            checkpoint=os.path.join(args.out, "search.json"), out=args.out, name="gain",
        )
    print(result.text)
    best = summaries(scene(), result.best)
    report = {
        "best": result.best,
        "gain": result.value,
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
