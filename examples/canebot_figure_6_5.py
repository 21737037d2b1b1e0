"""Figure 6.5 of the thesis for a CaneBot scene: distance per hop against the cane delay
CD, for the cane out CDC = 0.5 of each period (CD = 0 … 0.5) and CDC = 1 (CD = 0 … 1,
the thesis' trigger: out every second period), the cane always retracted and always
extended as lines, and the thesis' values as its text gives them (docs/physics.md §5.4:
the CDC = 0.5 peak of about 8.4 cm at CD = 0.1, about 40 % above both permanent cases,
so those near 6 cm; CDC = 1 mostly below them).

    python examples/canebot_figure_6_5.py scenes/canebot-identified.toml --out out/figure-6-5

Writes ``figure-6-5.png``/``.svg`` and ``figure-6-5.csv`` (every run) to ``--out`` and
prints the two curves. The scene's own cane schedule is kept (the thesis' trigger in
``scenes/canebot-identified.toml``); the runs share all cores.
"""

import argparse
import os
import sys

import numpy as np

import hopsim

#: The thesis' reading (docs/physics.md §5.4): the peak at CD = 0.1, m per hop, and its
#: ratio to both permanent cases.
THESIS_PEAK_CD = 0.1
THESIS_PEAK = 0.084
THESIS_PEAK_RATIO = 1.4
#: The CD values of the two panels, fractions of the motor period.
HALF_DELAYS = np.round(np.arange(0.0, 0.5 + 1e-9, 0.025), 3)
FULL_DELAYS = np.round(np.arange(0.0, 1.0 + 1e-9, 0.05), 3)
BASELINES = {
    "retracted": {"controller.cane_mode": "retracted"},
    "extended": {"controller.cane_mode": "extended"},
}


def curves(scene):
    """The two sweeps' tables and the permanent cases' distance per hop, m."""
    half = hopsim.sweep(
        scene,
        {"controller.cane_duration": [0.5], "controller.cane_delay": HALF_DELAYS},
        baselines=BASELINES,
    )
    full = hopsim.sweep(
        scene, {"controller.cane_duration": [1.0], "controller.cane_delay": FULL_DELAYS}
    )
    labels = half["label"]
    per_hop = half["distance_per_hop_m"]
    permanent = {name: float(per_hop[labels.index(name)]) for name in BASELINES}
    grid = [i for i, label in enumerate(labels) if label == "grid"]
    return half, full, grid, permanent


def draw(half, full, grid, permanent, title, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    thesis_permanent = THESIS_PEAK / THESIS_PEAK_RATIO
    panels = [
        (axes[0], "CDC = 0.5: cane out half of every period",
         half["controller.cane_delay"][grid], half["distance_per_hop_m"][grid], (0, 0.5)),
        (axes[1], "CDC = 1: cane out every second period",
         full["controller.cane_delay"], full["distance_per_hop_m"], (0, 1)),
    ]
    for ax, name, cd, h, xlim in panels:
        ax.plot(cd, 100 * h, "o-", color="C0", ms=4, label="hopsim: timed cane")
        ax.axhline(100 * permanent["retracted"], color="k", lw=1.5, label="hopsim: always retracted")
        ax.axhline(100 * permanent["extended"], color="0.55", lw=1.5, label="hopsim: always extended")
        ax.axhline(100 * thesis_permanent, color="C3", ls="--", lw=1.2,
                   label="thesis: both permanent cases ≈ 6 cm")
        if xlim[1] == 0.5:
            ax.plot([THESIS_PEAK_CD], [100 * THESIS_PEAK], "*", color="C3", ms=14,
                    label="thesis: peak 8.4 cm at CD = 0.1")
        ax.set_xlim(xlim[0] - 0.02 * xlim[1], xlim[1] * 1.02)
        ax.set_xlabel("cane delay CD (fraction of the motor period)")
        ax.set_title(name, fontsize=11)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("distance per hop (cm)")
    axes[0].set_ylim(0, max(10.0, 100 * np.nanmax(half["distance_per_hop_m"]) * 1.1))
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=9, frameon=False)
    fig.suptitle(title, fontsize=12)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    for ext in ("png", "svg"):
        path = os.path.join(out, f"figure-6-5.{ext}")
        tmp = path + ".part"
        fig.savefig(tmp, dpi=120, format=ext)
        os.replace(tmp, path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default="scenes/canebot-identified.toml")
    parser.add_argument("--out", default="out/figure-6-5")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scene = hopsim.Scene.load(args.scene)
    half, full, grid, permanent = curves(scene)
    csv_path = os.path.join(args.out, "figure-6-5.csv")
    with open(csv_path + ".part", "w", encoding="utf-8") as f:
        f.write(half.csv)
        f.write("".join(full.csv.splitlines(keepends=True)[1:]))
    os.replace(csv_path + ".part", csv_path)
    print(f"always retracted {100 * permanent['retracted']:.2f} cm per hop, "
          f"always extended {100 * permanent['extended']:.2f} cm per hop")
    for name, cd, h in [("CDC = 0.5", half["controller.cane_delay"][grid], half["distance_per_hop_m"][grid]),
                        ("CDC = 1", full["controller.cane_delay"], full["distance_per_hop_m"])]:
        print(name + ": " + " ".join(f"{c:g}:{100 * x:.2f}" for c, x in zip(cd, h)))
    try:
        draw(half, full, grid, permanent, f"Figure 6.5 for {scene.title}", args.out)
    except Exception as error:  # the runs' CSV is written: a figure must not lose them
        print(f"figure not drawn: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
