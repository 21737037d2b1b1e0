"""hopsim.sweep: local, in chunks, on a Dask LocalCluster, and against `hopsim sweep`."""

import subprocess

import numpy as np
import pytest

import hopsim
from test_simulation import MomentumImpulse

GRID = {"controller.torque": [0.12, 0.16, 0.2], "controller.impulse_limit": [0.05, 0.059]}
BASELINES = {"slow": {"controller.torque": 0.1}}


def comparable(table):
    """The rows without the wall time (the machine's, not the run's)."""
    w = table.columns.index("wall_time_s")
    return [row[:w] + row[w + 1 :] for row in table.rows]


@pytest.fixture(scope="module")
def local(robbit):
    return hopsim.sweep(robbit, GRID, baselines=BASELINES)


def test_rows_follow_the_grid_then_the_baselines(local):
    assert len(local) == 7
    assert local.columns[:5] == [
        "label",
        "controller.torque",
        "controller.impulse_limit",
        "status",
        "error",
    ]
    assert local["label"] == ["grid"] * 6 + ["slow"]
    np.testing.assert_array_equal(local["controller.torque"][:6], np.repeat(GRID["controller.torque"], 2))
    np.testing.assert_array_equal(local["controller.impulse_limit"][:6], np.tile(GRID["controller.impulse_limit"], 3))
    assert np.isnan(local["controller.torque"][6])
    assert local["status"] == ["ok"] * 7


def test_each_row_is_the_run_of_its_point(robbit, local):
    """Row 3 (torque 0.16, ζ0 0.059) is the run of that scene."""
    scene = robbit.with_overrides({"controller.torque": 0.16, "controller.impulse_limit": 0.059})
    summary = hopsim.Simulation(scene).run().summary
    assert local["mean_speed_mps"][3] == summary["mean_speed_mps"]
    assert local["hops"][3] == summary["hops"]


def test_chunks_give_the_same_rows(robbit, local):
    from hopsim import _hopsim

    parts = [
        _hopsim.sweep_csv(robbit, list(GRID.items()), BASELINES, start, start + 3, 1)
        for start in range(0, 7, 3)
    ]
    chunked = hopsim.SweepTable._from_csv_parts(parts)
    assert comparable(chunked) == comparable(local)


def test_dask_local_cluster_gives_the_same_table(robbit, local):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        on_dask = hopsim.sweep(robbit, GRID, baselines=BASELINES, client=client, chunk_size=2)
    assert on_dask.columns == local.columns
    assert comparable(on_dask) == comparable(local)


def test_matches_the_command_line_sweep(hopsim_bin, robbit_path, local, tmp_path):
    subprocess.run(
        [hopsim_bin, "sweep", str(robbit_path), "--set", "simulation.duration=2.0"]
        + ["--grid", "controller.torque=0.12,0.16,0.2"]
        + ["--grid", "controller.impulse_limit=0.05,0.059"]
        + ["--baseline", "slow:controller.torque=0.1", "--out", str(tmp_path), "--quiet"],
        check=True,
    )
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    cli = hopsim.SweepTable._from_csv_parts(["\n".join(lines) + "\n"])
    assert comparable(cli) == comparable(local)


def test_to_pandas(local):
    pd = pytest.importorskip("pandas")
    frame = local.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == local.columns and len(frame) == 7


def test_bad_sweeps_are_refused(robbit):
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.sweep(robbit, {"controller.torqe": [0.1]})
    assert "torque" in str(info.value)
    with pytest.raises(ValueError):
        hopsim.sweep(robbit, {"controller.torque": [0.1]}, baselines={"grid": {}})
    with pytest.raises(ValueError):
        hopsim.sweep(robbit, {})
    with pytest.raises(ValueError):
        hopsim.sweep(robbit, {"controller.torque": []})
    with pytest.raises(TypeError):
        hopsim.sweep(robbit, {"controller.torque": ["a"]})


def test_a_failed_run_is_a_row_with_its_error(robbit):
    table = hopsim.sweep(robbit, {"controller.impulse_limit": [0.059, -1.0]})
    assert table["status"][0] == "ok"
    assert table["status"][1] == "error" and table["error"][1]
    assert np.isnan(table["mean_speed_mps"][1])


class PythonMomentumImpulse:
    """A factory of Robbit's controller written in Python (test_simulation.py) whose
    torque is a parameter: `PythonMomentumImpulse(torque)` drives a simulation as the
    built-in controller with `controller.torque = torque` does, bit for bit."""

    def __init__(self, torque):
        self.torque = torque
        self.controller = None

    def __call__(self, sim):
        if self.controller is None:
            self.controller = MomentumImpulse(sim.scene)
            self.controller.torque = self.torque
        return self.controller(sim)


CONTROLLED_GRID = {"torque": [0.16, 0.2], "environment.friction": [0.8, 1.0]}
CONTROLLED_BASELINES = {"slow": {"torque": 0.1}}


@pytest.fixture(scope="module")
def controlled(robbit):
    return hopsim.sweep(
        robbit, CONTROLLED_GRID, baselines=CONTROLLED_BASELINES, controller=PythonMomentumImpulse
    )


def test_a_python_controller_sweep_equals_the_built_in_controller_sweep(robbit, controlled):
    """The factory's parameter `torque` is a grid axis beside the scene key
    `environment.friction`: every row equals the row of the sweep of the built-in
    controller over `controller.torque`, figure for figure (but the wall time)."""
    builtin = hopsim.sweep(
        robbit,
        {"controller.torque": CONTROLLED_GRID["torque"], "environment.friction": [0.8, 1.0]},
        baselines={"slow": {"controller.torque": 0.1}},
    )
    assert controlled.columns[:5] == ["label", "torque", "environment.friction", "status", "error"]
    assert controlled.columns[1:] != builtin.columns[1:]
    assert controlled.columns[3:] == builtin.columns[3:]
    assert controlled["status"] == ["ok"] * 5
    # The cells as text: the numbers are written as `hopsim sweep` writes them.
    assert comparable(controlled) == comparable(builtin)
    assert len(set(controlled["mean_speed_mps"])) > 1


def test_a_python_controller_sweep_on_dask_gives_the_same_table(robbit, controlled):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        on_dask = hopsim.sweep(
            robbit,
            CONTROLLED_GRID,
            baselines=CONTROLLED_BASELINES,
            controller=PythonMomentumImpulse,
            client=client,
            chunk_size=2,
        )
    assert on_dask.columns == controlled.columns
    assert comparable(on_dask) == comparable(controlled)


def test_a_python_controller_sweep_checks_its_scenes(robbit):
    with pytest.raises(hopsim.SceneError):
        hopsim.sweep(robbit, {"torque": [0.1], "environment.frction": [1.0]}, controller=PythonMomentumImpulse)
