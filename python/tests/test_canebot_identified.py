"""scenes/canebot-identified.toml and canebot-identified-robust.toml, the designs the targets
and robust searches found (docs/canebot.md, "The identified CaneBot"): their [meta] records
rebuild them from canebot-timed.toml, their gaits are the ones the docs report, and
examples/canebot_mechanism.py tells their flights apart."""

import importlib.util
import tomllib

import pytest

import hopsim
from conftest import REPO

SCENE = REPO / "scenes" / "canebot-identified.toml"
ROBUST = REPO / "scenes" / "canebot-identified-robust.toml"
BOTH = pytest.mark.parametrize("path", [SCENE, ROBUST], ids=["targets", "robust"])


def example(name):
    spec = importlib.util.spec_from_file_location(name, REPO / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def summary(scene, overrides=None):
    if overrides:
        scene = scene.with_overrides(overrides)
    return hopsim.Simulation(scene).run(frames=False).summary


@BOTH
def test_the_meta_record_rebuilds_the_scene_from_the_timed_cane_scene(path):
    record = tomllib.loads(path.read_text())["meta"]["search"]
    identify = example("canebot_identify")
    assert set(record["values"]) == set(identify.TARGET_PARAMS)
    for key, value in record["values"].items():
        lo, hi = identify.TARGET_PARAMS[key]
        assert lo <= value <= hi, key
    rebuilt = hopsim.Scene.load(
        REPO / "scenes" / "canebot-timed.toml",
        overrides={**identify.design(record["values"]), "controller.cane_schedule": "thesis"},
    )
    a, b = summary(rebuilt), summary(hopsim.Scene.load(path))
    # The same robot, bit for bit: the same hops and the same distance.
    assert a["hops"] == b["hops"]
    assert a["distance_m"] == b["distance_m"]


@BOTH
def test_the_gaits_the_docs_report(path):
    scene = hopsim.Scene.load(path)
    retracted = summary(scene, {"controller.cane_mode": "retracted"})
    extended = summary(scene, {"controller.cane_mode": "extended"})
    timed = summary(scene)
    assert retracted["gait"]["period"] == 1
    assert extended["gait"]["period"] == 2
    assert extended["mean_speed_mps"] < retracted["mean_speed_mps"]
    # The timed cane (0.1 / 0.5) ahead of both permanent cases per hop and in speed.
    per_hop = timed["distance_per_hop_m"]
    assert per_hop > 1.2 * max(retracted["distance_per_hop_m"], extended["distance_per_hop_m"])
    assert timed["mean_speed_mps"] > retracted["mean_speed_mps"]
    if path == ROBUST:
        # The thesis' size: the peak of CDC = 0.5 near 8.4 cm, between CD = 0.05 and 0.2.
        peak = max(
            (summary(scene, {"controller.cane_delay": cd})["distance_per_hop_m"], cd)
            for cd in (0.05, 0.1, 0.15, 0.2)
        )
        assert 0.075 < peak[0] < 0.095 and 0.05 <= peak[1] <= 0.2, peak


@BOTH
@pytest.mark.parametrize("mode", ["retracted", "extended", "timed"])
def test_every_flight_leaves_from_the_foot_or_the_cane(path, mode):
    mechanism = example("canebot_mechanism")
    scene = hopsim.Scene.load(path, overrides={"controller.cane_mode": mode})
    flights, held = mechanism.analyse(scene)
    assert len(flights) >= 10
    # The robot starts at rest on its foot: every flight has a last contact.
    assert all(f["from"] in ("foot", "cane") for f in flights)
    from_cane = sum(f["from"] == "cane" for f in flights)
    if mode == "retracted":
        # A retracted cane is not a contact: no flight can leave from it.
        assert from_cane == 0
    else:
        assert from_cane > 0
    if mode == "timed":
        # One window per motor period of the 10 s run (the thesis' trigger, CD + CDC < 1).
        assert len(held) == 28
        assert all(0.0 <= h <= 0.5 / 2.8 for h in held.values())
        blocked = [h for h in held.values() if h > 0.0]
        if path == SCENE:
            # The documented mechanism (docs/canebot.md): the trigger finds the tip in the
            # ground in every period and the cane comes out about 0.12 s later.
            assert all(0.08 < h < 0.16 for h in held.values()), held
        else:
            # A hop off the cane, then a period whose trigger finds the tip in the ground
            # (held back about 0.13 s) and a long hop off the foot: period 2.
            assert 12 <= len(blocked) <= 15 and all(0.08 < h < 0.16 for h in blocked), held
            long_hops = [f["length_m"] for f in flights[-10:] if f["from"] == "foot"]
            cane_hops = [f["length_m"] for f in flights[-10:] if f["from"] == "cane"]
            assert len(long_hops) == len(cane_hops) == 5
            assert min(long_hops) > 1.5 * max(cane_hops)


def test_figure_6_5_keeps_every_run_and_draws_both_panels(tmp_path):
    import csv
    import subprocess
    import sys

    script = REPO / "examples" / "canebot_figure_6_5.py"
    subprocess.run([sys.executable, str(script), str(SCENE), "--out", str(tmp_path)], check=True,
                   capture_output=True, text=True)
    with open(tmp_path / "figure-6-5.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    figure = example("canebot_figure_6_5")
    grid = [r for r in rows if r["label"] == "grid"]
    assert len(grid) == len(figure.HALF_DELAYS) + len(figure.FULL_DELAYS)
    assert sorted(r["label"] for r in rows if r["label"] != "grid") == ["extended", "retracted"]
    assert all(r["status"] == "ok" for r in rows)
    # The CSV's runs are the scene's: the retracted baseline is the retracted run.
    retracted = next(r for r in rows if r["label"] == "retracted")
    run = summary(hopsim.Scene.load(SCENE), {"controller.cane_mode": "retracted"})
    assert float(retracted["distance_per_hop_m"]) == pytest.approx(run["distance_per_hop_m"], rel=1e-12)
    for ext in ("png", "svg"):
        assert (tmp_path / f"figure-6-5.{ext}").stat().st_size > 10_000


def test_the_tolerance_moves_each_key_on_its_own_within_its_bounds():
    identify = example("canebot_identify")
    record = tomllib.loads(SCENE.read_text())["meta"]["search"]["values"]
    for offsets in identify.OFFSETS:
        # Each key its own offset (not one shared draw), each within [-1, 1].
        assert len(set(offsets.values())) == len(offsets)
        assert all(-1.0 <= o <= 1.0 for o in offsets.values())
        moved = identify.moved(record, offsets)
        for key, value in moved.items():
            lo, hi = identify.TARGET_PARAMS[key]
            assert lo <= value <= hi
            assert abs(value - record[key]) <= identify.TOLERANCE * abs(record[key]) + 1e-15
    # A key on its bound stays on it when pushed out.
    at_bound = dict(record, foot_length=0.34)
    pushed = identify.moved(at_bound, {k: 1.0 for k in record})
    assert pushed["foot_length"] == 0.34
