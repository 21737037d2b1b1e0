"""Brakes and shape switches of a batch, and restoring a reached state: a copy braked or
switched equals a Simulation stepped with the same lock or switch in an Actuation, bit for
bit."""

import numpy as np
import pytest

import hopsim
from conftest import SCENES


def passive(path):
    """The scene at ``path`` with its controller off (every controller key removed)."""
    model = hopsim.Scene.load(path).model
    keys = model._tables["controller"].keys
    return model.controller(**{k: None for k in keys if k != "type"}, type="passive")


def test_brakes_and_switches_equal_simulations_with_the_same_actuation():
    robbit = passive(SCENES / "robbit.toml").actuator("motor", joint="flywheel", kind="motor")
    scene = robbit.scene()
    n, blocks, steps = 6, 8, 25
    batch = hopsim.Batch(scene, n, threads=2, brakes=[(0, 1)])
    assert batch.brake_pairs == [(0, 1)] and batch.brakes.shape == (n, 1)
    sims = [hopsim.Simulation(scene) for _ in range(n)]
    for i, sim in enumerate(sims):
        u = np.array([0.1 * i, 0.0, 0.0, 3.0 * i])
        batch.set_state(i, scene.initial_q, u)
        sim.set_state(scene.initial_q, u)
    lock = hopsim.Actuation()
    lock.lock(0, 1)
    for b in range(blocks):
        braked = np.array([(i + b) % 2 == 0 for i in range(n)])
        batch.brakes[:, 0] = braked
        controls = np.full((n, 1), 0.05 * (b % 3 - 1))
        batch.step(steps, controls=controls)
        for i, sim in enumerate(sims):
            sim.control = controls[i]
            for _ in range(steps):
                sim.step(actuation=lock if braked[i] else hopsim.Actuation())
            assert np.array_equal(batch.q[i], sim.q) and np.array_equal(batch.u[i], sim.u)
            if braked[i]:  # the lock: θ̇_flywheel = θ̇_disc at the end of the step
                assert batch.u[i, 3] == pytest.approx(batch.u[i, 2], abs=1e-9)


def test_a_switched_shape_equals_a_simulation_switching_it():
    scene = passive(SCENES / "canebot.toml").scene()
    cane = scene.shapes.index("cane")
    batch = hopsim.Batch(scene, 2, threads=1, switches=[cane])
    assert batch.switch_shapes == [cane] and batch.switches.shape == (2, 1)
    sim = hopsim.Simulation(scene)
    pitching = np.array([0.0, 0.0, -3.0, 0.0])  # the foot rolls forward, onto the cane
    for i in range(2):
        batch.set_state(i, scene.initial_q, pitching)
    sim.set_state(scene.initial_q, pitching)
    batch.switches[1, 0] = True
    batch.step(400)
    switch = hopsim.Actuation()
    switch.switch_shape(cane, True)
    sim.step(actuation=switch)
    sim.step(399)
    assert np.array_equal(batch.q[1], sim.q) and np.array_equal(batch.u[1], sim.u)
    assert not np.array_equal(batch.q[0], batch.q[1])  # the cane changed the motion


def test_restore_accepts_a_reached_state_that_set_state_refuses():
    scene = hopsim.Scene.load(SCENES / "robbit.toml")
    batch = hopsim.Batch(scene, 1)
    q = scene.initial_q.copy()
    q[1] -= 1e-3  # 1 mm in the ground
    with pytest.raises(ValueError, match="inside the terrain"):
        batch.set_state(0, q, scene.initial_u)
    batch.set_state(0, q, scene.initial_u, restore=True)
    assert batch.q[0, 1] == q[1]
    with pytest.raises(ValueError):
        batch.set_state(0, q * np.nan, scene.initial_u, restore=True)


def test_brakes_and_switches_the_model_lacks_are_refused():
    scene = hopsim.Scene.load(SCENES / "robbit.toml")
    with pytest.raises(ValueError, match="brakes"):
        hopsim.Batch(scene, 2, brakes=[(0, 5)])
    with pytest.raises(ValueError, match="brakes"):
        hopsim.Batch(scene, 2, switches=[9])
