"""examples/hopper_hopping.py, the worked example of docs/mjcf.md: Gymnasium's hopper.xml,
imported as it is, hops forward under a Python controller; its CMA-ES search finds the
controller the example ships."""

import importlib.util

import numpy as np
import pytest

import hopsim
from conftest import REPO

pytest.importorskip("gymnasium", reason="the example reads gymnasium's hopper.xml")


def example():
    spec = importlib.util.spec_from_file_location("hopper_hopping", REPO / "examples" / "hopper_hopping.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_shipped_controller_hops_forward_without_falling():
    ex = example()
    scene = hopsim.Scene.load(ex.hopper_xml())
    gait = ex.rollout(scene, ex.PARAMS, duration=10.0)
    assert gait["fell_at"] is None
    # Hopping, not shuffling: the simulation's hop count and flights of 80 ms and more.
    assert gait["hops"] >= 20 and gait["flights"] >= 20, gait
    assert gait["distance"] >= 2.5, gait
    sim = gait["sim"]
    assert sim.q[1] > ex.MIN_HEIGHT and abs(sim.q[2]) < ex.MAX_PITCH
    # The run's energy account closes to the scheme's error: a small share of the work the
    # motors did.
    e = sim.energy()
    assert e["actuator_work"] > 0
    assert abs(e["balance_error"]) < 0.02 * e["actuator_work"], e


def test_the_search_finds_the_shipped_controller():
    ex = example()
    scene = hopsim.Scene.load(ex.hopper_xml())
    result = hopsim.optimize(ex.objective(scene), ex.BOUNDS, maximize=True, population=16, generations=40, seed=1)
    found = np.array([result.best[k] for k in ex.BOUNDS])
    shipped = np.array([ex.PARAMS[k] for k in ex.BOUNDS])
    np.testing.assert_array_equal(found, shipped)
