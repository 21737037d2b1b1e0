"""hopsim.optimize: CMA-ES (the engine of `hopsim optimize`) with Python objectives, on
local threads and on a Dask LocalCluster, resumed from a checkpoint, against the command line."""

import csv
import io
import math
import subprocess

import pytest

import hopsim

from conftest import REPO

#: The thrown point mass of the optimisation tests (docs/optimize.md).
PROJECTILE = REPO / "tests" / "data" / "optimize" / "projectile.toml"

PARAMS = {"initial.u.0": (0.0, 2.5), "initial.u.1": (0.0, 2.5)}


@pytest.fixture(scope="module")
def projectile():
    return hopsim.Scene.load(PROJECTILE, overrides={"simulation.dt": 1e-4})


def throw(scene):
    """The range of a throw, rejected above 2 J of launch energy (all dissipated on landing)."""

    def distance(values):
        summary = hopsim.Simulation(scene.with_overrides(values)).run(frames=False).summary
        if summary["energy"]["dissipated"] > 2.0:
            raise ValueError("more than 2 J")
        return summary["distance_m"]

    return distance


def test_finds_the_centre_of_a_shifted_sphere():
    centre = {"a": 0.7, "b": -1.3, "c": 2.1}
    result = hopsim.optimize(
        lambda v: sum((v[k] - centre[k]) ** 2 for k in centre),
        {k: (-5.0, 5.0) for k in centre},
        generations=200,
        seed=3,
    )
    assert result.value < 1e-10
    for k in centre:
        assert abs(result.best[k] - centre[k]) < 1e-5
    assert result.rejected == 0
    assert result.stop in ("MaxGenerations",) or result.stop.startswith("Converged: ")
    assert result.csv.splitlines()[0] == "generation,index,a,b,c,status,objective,best_so_far,error"


def test_rejections_are_recorded_and_integers_rounded():
    def f(v):
        if v["x"] > 0.5:
            raise ValueError("x above 0.5")
        return (v["x"] - 0.8) ** 2 + (v["n"] - 3.3) ** 2

    result = hopsim.optimize(f, {"x": (-2.0, 2.0), "n": (-9, 9, "int")}, generations=80)
    assert result.best["n"] == 3.0
    assert 0.49 < result.best["x"] <= 0.5
    rejected = [e for e in result.evaluations if e["objective"] is None]
    assert rejected and all("x above 0.5" in e["error"] for e in rejected)
    assert all(e["values"]["n"] == round(e["values"]["n"]) for e in result.evaluations)


def test_a_throw_goes_furthest_at_45_degrees(projectile, tmp_path):
    result = hopsim.optimize(
        throw(projectile), PARAMS, maximize=True, population=8, generations=25,
        out=str(tmp_path),
    )
    vx, vy = result.best["initial.u.0"], result.best["initial.u.1"]
    assert abs(math.degrees(math.atan2(vy, vx)) - 45.0) < 3.0
    assert result.value == pytest.approx(2 * 2.0 / 9.81, rel=5e-3)
    assert (tmp_path / "evaluations.csv").read_text() == result.csv
    assert (tmp_path / "convergence.png").stat().st_size > 0


def test_dask_local_cluster_gives_the_local_search(projectile):
    distributed = pytest.importorskip("distributed")
    kwargs = dict(maximize=True, population=6, generations=4, seed=5)
    local = hopsim.optimize(throw(projectile), PARAMS, **kwargs)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        on_dask = hopsim.optimize(throw(projectile), PARAMS, client=client, **kwargs)
    assert on_dask.evaluations == local.evaluations
    assert on_dask.best == local.best


def test_an_interrupted_search_resumes_to_the_uninterrupted_one(projectile, tmp_path):
    kwargs = dict(maximize=True, population=6, generations=6, seed=2)
    whole = hopsim.optimize(throw(projectile), PARAMS, **kwargs)
    calls = []

    def stops(values):
        calls.append(1)
        if len(calls) == 6 * 3 + 2:
            raise KeyboardInterrupt
        return throw(projectile)(values)

    path = str(tmp_path / "search.json")
    with pytest.raises(KeyboardInterrupt):
        hopsim.optimize(stops, PARAMS, checkpoint=path, threads=1, name="throw", **kwargs)
    resumed = hopsim.optimize(throw(projectile), PARAMS, checkpoint=path, name="throw", **kwargs)
    assert resumed.evaluations == whole.evaluations
    with pytest.raises(ValueError, match="another search"):
        hopsim.optimize(throw(projectile), PARAMS, checkpoint=path, name="other", **kwargs)


def test_a_finished_search_extends_to_a_longer_one(projectile, tmp_path):
    kwargs = dict(maximize=True, population=6, seed=3, name="throw")
    path = str(tmp_path / "search.json")
    short = hopsim.optimize(throw(projectile), PARAMS, checkpoint=path, generations=3, **kwargs)
    assert short.generations == 3
    longer = hopsim.optimize(throw(projectile), PARAMS, checkpoint=path, generations=5, **kwargs)
    planned = hopsim.optimize(throw(projectile), PARAMS, generations=5, **kwargs)
    assert longer.generations == 5
    assert longer.evaluations == planned.evaluations


def test_matches_the_command_line(hopsim_bin, projectile, tmp_path):
    out = tmp_path / "cli"
    subprocess.run(
        [hopsim_bin, "optimize", str(PROJECTILE), "--set", "simulation.dt=1e-4"]
        + ["--maximize", "distance_m", "--quiet"]
        + ["--param", "initial.u.0=0:2.5", "--param", "initial.u.1=0:2.5"]
        + ["--constraint", "energy.dissipated=:2", "--population", "6"]
        + ["--generations", "3", "--seed", "4", "--out", str(out)],
        check=True,
    )
    rows = list(csv.DictReader(io.StringIO((out / "evaluations.csv").read_text())))
    result = hopsim.optimize(
        throw(projectile), PARAMS, maximize=True, population=6, generations=3, seed=4
    )
    assert len(rows) == len(result.evaluations) == 18
    for row, e in zip(rows, result.evaluations):
        assert float(row["initial.u.0"]) == e["values"]["initial.u.0"]
        assert float(row["initial.u.1"]) == e["values"]["initial.u.1"]
        assert (row["status"] == "ok") == (e["objective"] is not None)
        if e["objective"] is not None:
            assert float(row["objective"]) == e["objective"]
