#!/usr/bin/env python3
"""Peer benchmarks of hopsim, interleaved in one run (called by benches/peers/run.sh).

LCPs: for each round and each .dat problem, Siconos' C lexicographic Lemke (siconos_lcp)
and hopsim's LemkeSolver (peer_lcp) are timed one after the other, in alternating order
(even rounds Siconos first, odd rounds hopsim first); each measurement is the median over K
batches of the time of one solve; the table shows the median over the rounds and the range
of the per-round ratios. Every measurement's z is checked against the other solver's.

Rollout: MuJoCo's native rollout (mujoco.rollout.rollout, in this process) of the planar
Robbit in robbit.xml, and hopsim's run loop on scenes/robbit.toml (peer_rollout), both
20 s = 100 000 steps of 2e-4 s, alternated the same way. Then the same MJCF file stepped by
both: gymnasium's hopper.xml, 10 s at its own 0.002 s, zero controls. Then batches: 256
Robbits (--batch-copies) for 1 s on all cores (--threads), MuJoCo's rollout with one MjData
per thread against hopsim's Batch.

Exit status: 0, or 1 (after the table) if a solver failed or returned a z that does not
solve the LCP. Different z that both solve it (an LCP may have several solutions) are
reported loudly too, with exit status 0.
"""

import argparse
import json
import tomllib
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

# (file in data/, label). The first four are the criterion benchmark's contact LCPs
# (crates/hopsim-lcp/benches/lemke.rs), the last three Siconos' own test problems.
PROBLEMS = [
    ("robbit_6x6.dat", "Robbit, 2 contacts"),
    ("contact_12.dat", "2 discs, 4 contacts"),
    ("contact_24.dat", "4 discs, 8 contacts"),
    ("contact_48.dat", "8 discs, 16 contacts"),
    ("lcp_deudeu.dat", "Siconos deudeu"),
    ("lcp_exp_murty.dat", "Siconos exp_murty"),
    ("lcp_trivial.dat", "Siconos trivial"),
]

# z agreement: |z_siconos - z_hopsim|_inf <= Z_TOL * max(1, |z|_inf).
Z_TOL = 1e-7

# Robbit's controller (docs/physics.md 5.3) is read from the scene hopsim runs (--scene) and
# emulated once in closed loop to get the open-loop controls that the timed MuJoCo rollout
# replays; robbit.xml has Table 5.1's bodies.
I_S, I_R = 3.004e-3, 1.543e-3
DURATION = 20.0  # s
# The MJCF rollout: gymnasium's hopper.xml with zero controls.
HOPPER_DURATION = 10.0  # s
HOPPER_TILT = 0.1  # rad, initial rooty
# The batch rollout: Robbits stepped together on all cores (MuJoCo's rollout with one MjData
# per thread, hopsim's Batch).
BATCH_DURATION = 1.0  # s


def loud(message):
    bar = "!" * 78
    print(f"\n{bar}\n{message}\n{bar}\n", flush=True)


def run_json(cmd):
    """Runs cmd, returns its stdout's JSON lines; exits with a clear message on failure."""
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(
            f"error: {' '.join(map(str, cmd))} exited with {proc.returncode}:\n{proc.stderr}"
        )
    return [json.loads(line) for line in proc.stdout.splitlines() if line.strip()]


def fmt_ns(ns):
    if ns >= 1e6:
        return f"{ns / 1e6:.2f} ms"
    if ns >= 1e4:
        return f"{ns / 1e3:.1f} µs"
    if ns >= 1e3:
        return f"{ns / 1e3:.2f} µs"
    return f"{ns:.0f} ns"


def fmt_rate(r):
    return f"{r:,.0f}".replace(",", " ")


def table(header, rows):
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    line = lambda r: "| " + " | ".join(str(c).ljust(w) for c, w in zip(r, widths)) + " |"
    out = [line(header), "|" + "|".join("-" * (w + 2) for w in widths) + "|"]
    out += [line(r) for r in rows]
    return "\n".join(out)


def z_mismatch(z_a, z_b):
    """None if the two z agree, else a description."""
    if len(z_a) != len(z_b):
        return f"sizes differ ({len(z_a)} vs {len(z_b)})"
    scale = max([1.0] + [abs(v) for v in z_a + z_b])
    diff = max(abs(a - b) for a, b in zip(z_a, z_b))
    if diff > Z_TOL * scale:
        return f"|dz|_inf = {diff:.3e} > {Z_TOL:g} * {scale:.3g}"
    return None


def read_dat(path):
    """M (list of rows) and q of a dense .dat file (the format of dat.rs)."""
    tokens = path.read_text().split()
    n = int(tokens[0])
    values = [float(v) for v in tokens[6:6 + n * n + n]]
    return [values[i * n:(i + 1) * n] for i in range(n)], values[n * n:]


def lcp_violation(m, q, z):
    """How far z is from solving the LCP, relative to the problem's scale: the largest of
    -min(z), -min(w), |z_i w_i| over (1 + |M|_inf |z|_inf + |q|_inf), w = M z + q."""
    w = [sum(a * b for a, b in zip(row, z)) + qi for row, qi in zip(m, q)]
    scale = 1.0 + max(abs(a) for row in m for a in row) * max(map(abs, z)) + max(map(abs, q))
    worst = max([-min(z), -min(w)] + [abs(a * b) for a, b in zip(z, w)])
    return max(worst, 0.0) / scale


def bench_lcps(args):
    rows, problems_out, failures = [], [], []
    files = []
    for name, label in PROBLEMS:
        path = Path(args.data) / name
        if not path.is_file():
            sys.exit(f"error: {path} is missing (benches/peers/data/ is committed data)")
        files.append((path, label))
    common = ["--batches", str(args.batches), "--batch-us", str(args.batch_us)]
    samples = {p: {"siconos": [], "hopsim": []} for p, _ in files}
    mismatches, warnings = {}, []
    last = {p: {} for p, _ in files}
    for r in range(args.rounds):
        for path, _ in files:
            order = ["siconos", "hopsim"] if r % 2 == 0 else ["hopsim", "siconos"]
            for who in order:
                binary = args.siconos if who == "siconos" else args.hopsim_lcp
                (res,) = run_json([binary, *common, str(path)])
                if res["status"] != "solved":
                    failures.append(f"{path.name}: {who} returned status {res['status']}")
                samples[path][who].append(res["median_ns"])
                last[path][who] = res
            bad = z_mismatch(last[path]["siconos"]["z"], last[path]["hopsim"]["z"])
            if bad and bad not in mismatches.setdefault(path, []):
                mismatches[path].append(bad)
        print(f"  LCP round {r + 1}/{args.rounds} done", file=sys.stderr, flush=True)
    for path, label in files:
        s, h = samples[path]["siconos"], samples[path]["hopsim"]
        ratios = [a / b for a, b in zip(s, h)]
        ms, mh = statistics.median(s), statistics.median(h)
        ls, lh = last[path]["siconos"], last[path]["hopsim"]
        agree = "yes"
        if mismatches.get(path):
            m, q = read_dat(path)
            bad = {who: lcp_violation(m, q, res["z"]) for who, res in (("Siconos", ls), ("hopsim", lh))}
            invalid = [f"{who}'s z violates the LCP by {v:.1e}" for who, v in bad.items() if v > Z_TOL]
            what = f"{path.name}: Siconos and hopsim return different z ({'; '.join(mismatches[path])})"
            if invalid:
                failures.append(f"{what}: {'; '.join(invalid)}")
                agree = "NO: " + ", ".join(w for w, v in bad.items() if v > Z_TOL) + " wrong"
            else:
                warnings.append(f"{what}; both solve the LCP (violation {bad['Siconos']:.1e} "
                                f"and {bad['hopsim']:.1e}): it has more than one solution and the "
                                "two pivoting paths end at different ones")
                agree = "NO (both valid)"
        rows.append([
            f"{path.stem} ({label})",
            str(lh["n"]),
            fmt_ns(ms),
            fmt_ns(mh),
            f"{ms / mh:.2f}×",
            f"{min(ratios):.2f}–{max(ratios):.2f}",
            f"{ls['pivots']} / {lh['pivots']}",
            agree,
        ])
        problems_out.append({
            "problem": path.stem, "n": lh["n"], "siconos_ns": s, "hopsim_ns": h,
            "siconos_median_ns": ms, "hopsim_median_ns": mh, "ratio": ms / mh,
            "siconos_pivots": ls["pivots"], "hopsim_pivots": lh["pivots"],
            "siconos_batch": ls["batch"], "hopsim_batch": lh["batch"],
            "same_z": agree,
        })
    header = ["problem", "n", "Siconos median", "hopsim median", "ratio Siconos/hopsim",
              "ratio range over rounds", "pivots S / h", "same z"]
    return table(header, rows), problems_out, failures, warnings


def scene_control(path):
    """(torque N m, impulse limit N m s, rearm timeout s) of the scene's momentum-impulse
    controller; the emulation below knows the touchdown release only."""
    with open(path, "rb") as f:
        c = tomllib.load(f)["controller"]
    if c.get("type") != "momentum_impulse" or c.get("release", "touchdown") != "touchdown":
        sys.exit(f"error: {path}: the MuJoCo peer emulates the momentum-impulse controller "
                 "with release = \"touchdown\" only")
    return float(c["torque"]), float(c["impulse_limit"]), float(c.get("rearm_timeout", 1.0))


def robbit_controls(mujoco, np, model, control):
    """Robbit's momentum-impulse controller run once in closed loop on the MuJoCo model:
    motor on in stance until the stored impulse reaches the limit, then the brake (held
    until the relative rate has dropped to 1 %), motor off until touchdown or the rearm
    timeout. `control` is (torque, impulse limit, rearm timeout). Returns the controls
    (nstep x 2: motor torque, brake) and a description."""
    torque, impulse_limit, rearm_timeout = control
    data = mujoco.MjData(model)
    nstep = int(round(DURATION / model.opt.timestep))
    i_red = I_S * I_R / (I_S + I_R)
    psi = model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "psi")]
    x = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "x")]
    ctrl = np.zeros((nstep, model.nu))
    stance, since, airborne, braking, brake_rate = True, 0.0, False, False, 0.0
    takeoffs, was_contact, contact_steps, brakes = 0, True, 0, 0
    for k in range(nstep):
        contact = data.ncon > 0
        contact_steps += contact
        if not stance:
            if (airborne and contact) or (contact and data.time - since >= rearm_timeout):
                stance = True
            else:
                airborne = airborne or not contact
        takeoffs += was_contact and not contact
        was_contact = contact
        rate = data.qvel[psi]
        if stance and i_red * rate >= impulse_limit:
            stance, since, airborne, braking, brake_rate = False, data.time, False, True, rate
            brakes += 1
        if braking and abs(rate) < 0.01 * abs(brake_rate):
            braking = False
        ctrl[k] = (torque, 0.0) if stance else (0.0, 1.0 if braking else 0.0)
        data.ctrl[:] = ctrl[k]
        mujoco.mj_step(model, data)
    return ctrl, {"brakes": brakes, "takeoffs": int(takeoffs),
                  "contact_steps": int(contact_steps), "distance_m": float(data.qpos[x])}


def import_mujoco():
    try:
        import mujoco
        import mujoco.rollout
        import numpy as np
    except ImportError as e:
        sys.exit(f"error: MuJoCo's Python package is missing ({e}); install it with "
                 "`python3 -m pip install 'mujoco>=3.2'` (run.sh does this)")
    return mujoco, np


def rollout_timer(mujoco, np, model, control, data=None, copies=1, threads=1):
    """A function timing MuJoCo's native rollout of `model` with the open-loop `control`
    (nstep x nu) from the state in `data` (default: the model's initial state), `copies`
    copies on `threads` threads; it returns the copies' steps together per second."""
    nstep = control.shape[0]
    data = data or mujoco.MjData(model)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.zeros(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state0, spec)
    out = np.zeros((copies, nstep, state0.size))
    initial = np.repeat(state0[None], copies, axis=0)
    control = np.repeat(control[None], copies, axis=0)
    datas = data if threads == 1 else [mujoco.MjData(model) for _ in range(threads)]

    def rate():
        start = time.perf_counter()
        mujoco.rollout.rollout(model, datas, initial, control, state=out)
        return copies * nstep / (time.perf_counter() - start)

    return rate


def interleaved_rollouts(args, mujoco_rate, nstep, hopsim_cmd, label):
    """Times `mujoco_rate` (see `rollout_timer`) against hopsim's `peer_rollout` command,
    alternating which goes first; returns (table row, MuJoCo rates, hopsim rates, hopsim's
    last JSON line)."""
    mujoco_rate()  # warm-up
    mj, hs = [], []
    hop = None
    for r in range(args.rounds):
        order = ["mujoco", "hopsim"] if r % 2 == 0 else ["hopsim", "mujoco"]
        for who in order:
            if who == "mujoco":
                mj.append(statistics.median(mujoco_rate() for _ in range(args.rollout_runs)))
            else:
                (hop,) = run_json([args.hopsim_rollout, "--runs", str(args.rollout_runs),
                                   *hopsim_cmd])
                hs.append(hop["median_steps_per_s"])
        print(f"  {label}: round {r + 1}/{args.rounds} done", file=sys.stderr, flush=True)
    if hop["steps"] != nstep:
        sys.exit(f"error: {label}: hopsim ran {hop['steps']} steps, MuJoCo {nstep}")
    mm, mh = statistics.median(mj), statistics.median(hs)
    ratios = [b / a for a, b in zip(mj, hs)]
    row = [f"{label}, {fmt_rate(nstep)} steps", fmt_rate(mm), fmt_rate(mh), f"{mh / mm:.2f}×",
           f"{min(ratios):.2f}–{max(ratios):.2f}"]
    return row, mj, hs, hop


def bench_rollout(args):
    mujoco, np = import_mujoco()
    model = mujoco.MjModel.from_xml_path(str(HERE / "robbit.xml"))
    ctrl, info = robbit_controls(mujoco, np, model, scene_control(args.scene))
    row, mj, hs, hop = interleaved_rollouts(
        args, rollout_timer(mujoco, np, model, ctrl), ctrl.shape[0], [args.scene],
        f"Robbit, {DURATION:g} s")
    note = (f"Robbit's trajectories (not the same: soft against rigid contact, damper "
            f"against lock brake): MuJoCo {mujoco.__version__}: {info['brakes']} brakes, "
            f"{info['takeoffs']} contact losses, in contact in {info['contact_steps']} of "
            f"{ctrl.shape[0]} steps, x {info['distance_m']:+.2f} m; hopsim: {hop['hops']} "
            f"hops, x {hop['distance_m']:+.2f} m (the two x axes point opposite ways).")
    result = {"mujoco_version": mujoco.__version__, "mujoco_steps_per_s": mj,
              "hopsim_steps_per_s": hs, "mujoco_median": statistics.median(mj),
              "hopsim_median": statistics.median(hs),
              "ratio": statistics.median(hs) / statistics.median(mj),
              "mujoco_trajectory": info,
              "hopsim_trajectory": {"hops": hop["hops"], "distance_m": hop["distance_m"]}}
    return row, note, result


def hopper_xml():
    """Gymnasium's hopper.xml (the model file users run), from the installed package."""
    try:
        import gymnasium
    except ImportError as e:
        sys.exit(f"error: the MJCF rollout needs gymnasium's hopper.xml ({e}); install it "
                 "with `python3 -m pip install gymnasium` (run.sh does this)")
    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "hopper.xml"


def bench_hopper(args):
    """The same MJCF file stepped by both at its own timestep (0.002 s), single thread, with
    zero controls from the standing pose tilted by HOPPER_TILT: the limp hopper falls and
    lies on the floor. (Untilted, it stands on its foot: an equilibrium that hopsim's rigid
    contact keeps until round-off tips it, several seconds later than MuJoCo's soft one.)"""
    mujoco, np = import_mujoco()
    path = hopper_xml()
    model = mujoco.MjModel.from_xml_path(str(path))
    nstep = int(round(HOPPER_DURATION / model.opt.timestep))
    ctrl = np.zeros((nstep, model.nu))
    data = mujoco.MjData(model)
    data.qpos[2] = HOPPER_TILT  # rooty: the coordinates are MuJoCo's qpos in both
    row, mj, hs, hop = interleaved_rollouts(
        args, rollout_timer(mujoco, np, model, ctrl, data), nstep,
        ["--set", f"simulation.duration={HOPPER_DURATION}", "--set",
         f"initial.q.2={HOPPER_TILT}", str(path)],
        f"Hopper (MJCF), {HOPPER_DURATION:g} s")
    data = mujoco.MjData(model)
    data.qpos[2] = HOPPER_TILT
    for _ in range(nstep):
        mujoco.mj_step(model, data)
    note = (f"Hopper: gymnasium's hopper.xml at dt = {model.opt.timestep:g} s, no control, "
            f"tilted {HOPPER_TILT:g} rad; root x after {HOPPER_DURATION:g} s: MuJoCo "
            f"{data.qpos[0]:+.3f} m, hopsim {hop['distance_m']:+.3f} m.")
    result = {"mujoco_steps_per_s": mj, "hopsim_steps_per_s": hs,
              "ratio": statistics.median(hs) / statistics.median(mj)}
    return row, note, result


def bench_batch(args):
    """`--batch-copies` Robbits stepped together on `--threads` threads for BATCH_DURATION:
    MuJoCo's rollout of robbit.xml with one MjData per thread, against hopsim's `Batch`
    (peer_rollout --batch); the speed is the copies' steps together per second."""
    mujoco, np = import_mujoco()
    model = mujoco.MjModel.from_xml_path(str(HERE / "robbit.xml"))
    ctrl, _ = robbit_controls(mujoco, np, model, scene_control(args.scene))
    nstep = int(round(BATCH_DURATION / model.opt.timestep))
    n, threads = args.batch_copies, args.threads
    timer = rollout_timer(mujoco, np, model, ctrl[:nstep], copies=n, threads=threads)
    row, mj, hs, _ = interleaved_rollouts(
        args, timer, nstep,
        ["--batch", str(n), "--threads", str(threads), "--set",
         f"simulation.duration={BATCH_DURATION}", args.scene],
        f"{n} Robbits, {threads} threads, {BATCH_DURATION:g} s")
    result = {"copies": n, "threads": threads, "mujoco_steps_per_s": mj,
              "hopsim_steps_per_s": hs, "ratio": statistics.median(hs) / statistics.median(mj)}
    return row, result


def machine():
    cpu = platform.processor() or "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} CPUs"


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--siconos", required=True, help="the compiled siconos_lcp")
    p.add_argument("--hopsim-lcp", required=True, help="hopsim-lcp's example peer_lcp")
    p.add_argument("--hopsim-rollout", required=True, help="hopsim-sim's example peer_rollout")
    p.add_argument("--data", default=str(HERE / "data"))
    p.add_argument("--scene", default=str(HERE.parent.parent / "scenes" / "robbit.toml"))
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--batches", type=int, default=31)
    p.add_argument("--batch-us", type=float, default=200.0)
    p.add_argument("--rollout-runs", type=int, default=3)
    p.add_argument("--only", choices=["lcp", "rollout", "hopper", "batch"])
    p.add_argument("--batch-copies", type=int, default=256)
    p.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    p.add_argument("--json", help="also write the raw measurements here")
    args = p.parse_args()

    started = time.strftime("%Y-%m-%d %H:%M %Z")
    load0 = os.getloadavg()
    lcp_table = rollout_table = rollout_note = None
    failures, warnings, raw = [], [], {"date": started, "machine": machine()}
    if args.only in (None, "lcp"):
        lcp_table, raw["lcp"], failures, warnings = bench_lcps(args)
    rollout_rows, notes = [], []
    if args.only in (None, "rollout"):
        row, note, raw["rollout"] = bench_rollout(args)
        rollout_rows.append(row)
        notes.append(note)
    if args.only in (None, "hopper"):
        row, note, raw["hopper"] = bench_hopper(args)
        rollout_rows.append(row)
        notes.append(note)
    if args.only in (None, "batch"):
        row, raw["batch"] = bench_batch(args)
        rollout_rows.append(row)
    if rollout_rows:
        rollout_table = table(["rollout", "MuJoCo steps/s", "hopsim steps/s",
                               "ratio hopsim/MuJoCo", "ratio range over rounds"], rollout_rows)
        rollout_note = "\n".join(notes)
    load1 = os.getloadavg()
    raw["loadavg_start_end"] = [load0[0], load1[0]]

    print(f"\nPeer benchmarks, {started}; {raw['machine']}; load average "
          f"{load0[0]:.2f} at the start, {load1[0]:.2f} at the end.")
    print(f"Interleaved: {args.rounds} rounds, alternating which peer goes first.")
    if lcp_table:
        print(f"\nLCP: ns per solve, median over {args.rounds} rounds of (median over "
              f"{args.batches} batches of ≥ {args.batch_us:g} µs); ratio > 1: hopsim faster.\n")
        print(lcp_table)
    if rollout_table:
        print(f"\nRollout: steps per second of wall time, median over {args.rounds} rounds of "
              f"(median of {args.rollout_runs} runs); ratio > 1: hopsim faster.\n")
        print(rollout_table)
        print(f"\n{rollout_note}")
    if args.json:
        Path(args.json).write_text(json.dumps(raw, indent=1))
        print(f"\nRaw measurements: {args.json}")
    if warnings:
        loud("MISMATCH (different z, both valid):\n" + "\n".join(warnings))
    if failures:
        loud("MISMATCH / FAILURE:\n" + "\n".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
