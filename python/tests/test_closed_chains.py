"""Closed chains from Python (docs/python.md, "Closed chains from Python"): the documented
four-bar built with ``Model.loop`` runs with its loop closed and its open start refused
with the gap; it moves as ``scenes/classic/four-bar.toml`` does, bit for bit; and
``examples/five_bar_hopper.py`` hops forward and in place, stepped from Python."""

import re
import subprocess
import sys

import numpy as np

import hopsim
from conftest import REPO, SCENES


def closed_chains_example():
    """The first Python block of docs/python.md's "Closed chains from Python"."""
    text = (REPO / "docs" / "python.md").read_text()
    section = text.split("### Closed chains from Python", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_documented_four_bar_runs_and_an_open_start_is_refused():
    namespace = {}
    exec(compile(closed_chains_example(), "docs/python.md", "exec"), namespace)
    summary = namespace["trajectory"].summary
    assert summary["max_loop_error_m"] <= 1e-10
    assert summary["lcp"]["failures"] == 0
    message = namespace["message"]
    assert "coupler-rocker" in message and "open" in message, message


def test_the_four_bar_in_code_moves_as_the_gallery_scene():
    namespace = {}
    exec(compile(closed_chains_example(), "docs/python.md", "exec"), namespace)
    gallery = hopsim.Scene.load(SCENES / "classic" / "four-bar.toml",
                                overrides={"simulation.duration": 2.0})
    ours, theirs = namespace["trajectory"], hopsim.Simulation(gallery).run()
    # The same bodies, masses and loop, the inertias written as fractions: the same motion
    # to rounding.
    assert np.abs(ours.q[-1] - theirs.q[-1]).max() < 1e-9


def run_example(*args):
    out = subprocess.run(
        [sys.executable, str(REPO / "examples" / "five_bar_hopper.py"), *args],
        capture_output=True, text=True, timeout=600, check=False,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout


def test_the_five_bar_example_hops_forward_and_in_place():
    forward = run_example("--duration", "2")
    hops, distance = re.search(r"(\d+) hops in 2\.0 s, (-?[\d.]+) m", forward).groups()
    assert int(hops) >= 5 and float(distance) > 0.3, forward
    in_place = run_example("--duration", "2", "--sweep", "0")
    hops, distance = re.search(r"(\d+) hops in 2\.0 s, (-?[\d.]+) m", in_place).groups()
    assert int(hops) >= 5 and abs(float(distance)) < 1e-3, in_place
