"""Bodies, shapes, joints and actuators by name or index; per-shape contact flags and
forces on a simulation and, filled in place, on a batch."""

import numpy as np
import pytest

import hopsim


def test_names_follow_the_scene(robbit):
    sim = hopsim.Simulation(robbit)
    assert sim.body_names == [b["name"] for b in robbit.bodies] == ["disc", "flywheel"]
    assert sim.shape_names == robbit.shapes == ["disc"]
    # The floating base has no joint; the flywheel's pivot is named after it.
    assert sim.joint_names == ["flywheel"]
    batch = hopsim.Batch(robbit, 2, threads=1)
    assert batch.body_names == sim.body_names and batch.shape_names == sim.shape_names
    assert batch.joint_names == sim.joint_names and batch.actuator_names == []


def test_commands_by_name_equal_commands_by_index(robbit):
    """A motor torque, a brake and a kick given by names act as the same commands by
    indices: the two runs are equal bit for bit."""
    by_name, by_index = hopsim.Simulation(robbit), hopsim.Simulation(robbit)
    named, indexed = by_name.actuation(), hopsim.Actuation()
    for step in range(600):
        named.clear()
        indexed.clear()
        if step < 400:
            named.torque("flywheel", 0.3, reaction="disc")
            indexed.torque(1, 0.3, reaction=0)
        elif step == 400:
            named.brake("disc", "flywheel")
            indexed.brake(0, 1)
        else:
            named.joint_force("flywheel", -0.01)
            indexed.joint_force(1, -0.01)
            named.rotational_impulse("disc", 1e-4, reaction="flywheel")
            indexed.rotational_impulse(0, 1e-4, reaction=1)
        by_name.step(actuation=named)
        by_index.step(actuation=indexed)
    np.testing.assert_array_equal(by_name.q, by_index.q)
    np.testing.assert_array_equal(by_name.u, by_index.u)
    assert by_name.u[3] != 0.0


def test_unknown_names_and_indices_are_refused_naming_the_valid_ones(robbit):
    sim = hopsim.Simulation(robbit)
    a = sim.actuation()
    with pytest.raises(KeyError, match=r'no body named .*wheel.*; the bodies are \["disc", "flywheel"\]'):
        a.torque("wheel", 1.0)
    with pytest.raises(KeyError, match=r'no joint named .*disc.*; the joints are \["flywheel"\]'):
        a.joint_force("disc", 1.0)
    with pytest.raises(KeyError, match=r'no shape named .*cane.*; the shapes are \["disc"\]'):
        a.switch_shape("cane", True)
    with pytest.raises(IndexError, match=r"body 2 does not exist"):
        a.lock(0, 2)
    with pytest.raises(TypeError, match="name \\(str\\) or index \\(int\\)"):
        a.point_impulse(1.5, (0.0, 1.0))
    with pytest.raises(TypeError, match="takes indices only"):
        hopsim.Actuation().torque("disc", 1.0)
    with pytest.raises(KeyError, match="no actuator named .*motor.*; the actuators are \\[\\]"):
        sim.set_control("motor", 1.0)
    assert repr(a) == "Actuation(0 torques, 0 joint forces, 0 impulses, 0 locks, 0 events)"
    # An actuation made for a scene is an actuation like any other.
    b = hopsim.Actuation(robbit)
    b.torque("flywheel", 0.1)
    sim.step(actuation=b)


def test_a_resting_disc_carries_the_weight_on_its_shape(robbit):
    """Robbit at rest on the ground: its one shape is in contact, with the normal force of
    the weight m g and no tangential force (a percussion m g Δt per step)."""
    sim = hopsim.Simulation(robbit)
    sim.step(20, actuation=hopsim.Actuation())
    weight = sum(b["mass"] for b in robbit.bodies) * robbit.settings["gravity"]
    np.testing.assert_array_equal(sim.shape_in_contact(), [True])
    forces = sim.shape_contact_forces()
    assert forces.shape == (1, 2)
    assert forces[0, 0] == pytest.approx(weight, rel=1e-9)
    assert forces[0, 1] == pytest.approx(0.0, abs=1e-9)
    kick = sim.actuation()
    kick.point_impulse("disc", (0.0, 3.0))
    sim.step(actuation=kick)
    np.testing.assert_array_equal(sim.shape_in_contact(), [False])
    np.testing.assert_array_equal(sim.shape_contact_forces(), [[0.0, 0.0]])


def test_batch_shape_arrays_are_the_copies_own_filled_in_place(robbit):
    """Per-shape flags (n, shapes) and forces (n, shapes, 2) of a batch equal each copy's
    single simulation, in the same arrays after every step."""
    n = 4
    batch = hopsim.Batch(robbit, n, threads=2)
    flags, forces = batch.shape_in_contact, batch.shape_contact_forces
    assert flags.shape == (n, 1) and forces.shape == (n, 1, 2)
    assert not flags.flags.writeable
    singles = [hopsim.Simulation(robbit) for _ in range(n)]
    for i, sim in enumerate(singles):
        q = np.array(robbit.initial_q)
        u = np.array([0.5 * i, 0.0, 0.0, 0.0])
        batch.set_state(i, q, u)
        sim.set_state(q, u)
    seen_flight = False
    for _ in range(40):
        batch.step(50)
        for i, sim in enumerate(singles):
            sim.step(50)
            np.testing.assert_array_equal(flags[i], sim.shape_in_contact())
            np.testing.assert_array_equal(forces[i], sim.shape_contact_forces())
            seen_flight |= not flags[i, 0]
        assert batch.shape_in_contact is flags and batch.shape_contact_forces is forces
    assert flags.any() and seen_flight
