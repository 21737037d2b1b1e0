"""Speed of the Python package against the command line (docs/python.md, "Speed").

Measures, on Robbit (scenes/robbit.toml):

1. ``Simulation.run`` steps per second against ``hopsim run`` (both from the run
   summary's ``steps_per_s``, best of ``--repeat``);
2. the overhead of one ``Simulation.step()`` call from Python: a loop of single steps
   against one ``step(n)`` call, per step; the same with an ``Actuation`` (a controller
   written in Python that only commands a torque);
3. ``hopsim.sweep`` of an ``N × N`` grid on all local cores against the same sweep on a
   Dask ``LocalCluster`` of 2 worker processes.

    python python/benches/bench.py --hopsim-bin target/release/hopsim [--grid 30]

Prints one line per figure and, with ``--json FILE``, writes them as JSON.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import hopsim

REPO = Path(__file__).resolve().parents[2]
ROBBIT = REPO / "scenes" / "robbit.toml"


def best(times):
    return min(times)


def run_speed(bin_path: str, duration: float, repeat: int) -> dict:
    scene = hopsim.Scene.load(ROBBIT, overrides={"simulation.duration": duration})
    python = []
    for _ in range(repeat):
        python.append(hopsim.Simulation(scene).run().summary["steps_per_s"])
    cli = []
    with tempfile.TemporaryDirectory() as tmp:
        summary = Path(tmp) / "s.json"
        for _ in range(repeat):
            subprocess.run(
                [bin_path, "run", str(ROBBIT), "--duration", str(duration), "--quiet"]
                + ["--summary", str(summary)],
                check=True,
            )
            cli.append(json.loads(summary.read_text())["steps_per_s"])
    return {
        "run_steps_per_s_python": max(python),
        "run_steps_per_s_cli": max(cli),
        "run_python_vs_cli": max(python) / max(cli),
    }


def step_overhead(steps: int, repeat: int) -> dict:
    scene = hopsim.Scene.load(ROBBIT)
    bulk, single, actuated = [], [], []
    for _ in range(repeat):
        sim = hopsim.Simulation(scene)
        t0 = time.perf_counter()
        sim.step(steps)
        bulk.append(time.perf_counter() - t0)

        sim = hopsim.Simulation(scene)
        step = sim.step
        t0 = time.perf_counter()
        for _ in range(steps):
            step()
        single.append(time.perf_counter() - t0)

        sim = hopsim.Simulation(scene)
        a = hopsim.Actuation()
        c = scene.controller
        fly, disc, torque = c["flywheel"], scene.bodies[c["flywheel"]]["parent"], c["torque"]
        t0 = time.perf_counter()
        for _ in range(steps):
            a.clear()
            a.torque(fly, torque, disc)
            sim.step(actuation=a)
        actuated.append(time.perf_counter() - t0)
    per_step = best(bulk) / steps
    return {
        "step_time_rust_s": per_step,
        "step_call_overhead_s": best(single) / steps - per_step,
        "step_with_actuation_overhead_s": best(actuated) / steps - per_step,
    }


def sweep_speed(size: int, duration: float) -> dict:
    from distributed import Client, LocalCluster

    scene = hopsim.Scene.load(ROBBIT, overrides={"simulation.duration": duration})
    grid = {
        "controller.torque": np.linspace(0.1, 0.3, size),
        "controller.impulse_limit": np.linspace(0.04, 0.07, size),
    }
    t0 = time.perf_counter()
    local = hopsim.sweep(scene, grid)
    local_s = time.perf_counter() - t0
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("hopsim"))  # workers start and import first
        t0 = time.perf_counter()
        on_dask = hopsim.sweep(scene, grid, client=client)
        dask_s = time.perf_counter() - t0
    w = local.columns.index("wall_time_s")
    same = [r[:w] + r[w + 1 :] for r in local.rows] == [r[:w] + r[w + 1 :] for r in on_dask.rows]
    return {
        "sweep_grid": f"{size}x{size}",
        "sweep_duration_s": duration,
        "sweep_local_wall_s": local_s,
        "sweep_dask_wall_s": dask_s,
        "sweep_dask_vs_local": dask_s / local_s,
        "sweep_identical_rows": same,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--hopsim-bin", default="hopsim", help="the hopsim command line")
    parser.add_argument("--duration", type=float, default=20.0, help="run length, s")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--steps", type=int, default=20000, help="steps of the overhead test")
    parser.add_argument("--grid", type=int, default=30, help="sweep grid size N (N × N)")
    parser.add_argument("--sweep-duration", type=float, default=20.0, help="sweep run length, s")
    parser.add_argument("--skip-sweep", action="store_true")
    parser.add_argument("--only-sweep", action="store_true")
    parser.add_argument("--json", type=Path, help="write the figures here")
    args = parser.parse_args()
    figures = {}
    if not args.only_sweep:
        figures.update(run_speed(args.hopsim_bin, args.duration, args.repeat))
        figures.update(step_overhead(args.steps, args.repeat))
    if not args.skip_sweep:
        figures.update(sweep_speed(args.grid, args.sweep_duration))
    for key, value in figures.items():
        if isinstance(value, float) and key.endswith("overhead_s") or key == "step_time_rust_s":
            print(f"{key:34} {value * 1e6:10.3f} µs")
        elif isinstance(value, float):
            print(f"{key:34} {value:10.4g}")
        else:
            print(f"{key:34} {value}")
    if args.json:
        args.json.write_text(json.dumps(figures, indent=2) + "\n")


if __name__ == "__main__":
    main()
