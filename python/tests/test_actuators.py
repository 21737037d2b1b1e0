"""Actuators from Python (docs/python.md, "Actuators"): controls set by array, name or
index and held from step to step, the actuators' generalised forces with their ranges
clamping, control signals, MuJoCo models' actuators, and errors."""

import math

import numpy as np
import pytest

import hopsim

#: A wheel of inertia I turning about its centre of mass (no load) and a rod of mass M
#: whose centre of mass hangs L below its pin.
I_WHEEL, M, L, G = 0.1, 2.0, 0.5, 9.81


def machine(**wheel_control):
    model = hopsim.Model("actuated")
    model.simulation(duration=1.0, dt=1e-3, gravity=G)
    model.environment(terrain="none")
    model.body("wheel", base="pinned", pivot=[0.0, 0.0], mass=1.0, inertia=I_WHEEL)
    model.body("rod", base="pinned", pivot=[1.0, 0.0], com=[0.0, -L], mass=M, inertia=0.05,
               damping=3.0)
    model.actuator("spin", joint="wheel", kind="motor", gear=2.0, force_range=[-1.5, 1.5],
                   **wheel_control)
    model.actuator("hold", joint="rod", kind="position", kp=40.0, ctrl_range=[-1.0, 1.0])
    model.initial(q=[0.0, 0.0])
    return model


def test_controls_are_set_by_array_name_or_index_and_held():
    sim = hopsim.Simulation(machine().scene())
    assert sim.actuator_names == ["spin", "hold"]
    np.testing.assert_array_equal(sim.control, [0.0, 0.0])
    sim.control = [0.5, 0.2]
    sim.set_control("hold", 0.3)
    sim.set_control(0, 0.25)
    np.testing.assert_array_equal(sim.control, [0.25, 0.3])
    sim.step(100)
    np.testing.assert_array_equal(sim.control, [0.25, 0.3])
    # A constant torque gear · ctrl = 0.5 N m on the free wheel: ω = τ t / I, exactly.
    assert sim.u[0] == pytest.approx(0.5 * 0.1 / I_WHEEL, rel=1e-12)


def test_actuator_forces_are_gear_times_the_clamped_force():
    sim = hopsim.Simulation(machine().scene())
    # The motor's force 4 is clamped to 1.5 and geared by 2; the servo's control 3 is
    # clamped to 1, its force kp (1 − q) at q = 0.
    sim.control = [4.0, 3.0]
    np.testing.assert_allclose(sim.actuator_forces(), [3.0, 40.0], rtol=0, atol=1e-12)
    sim.set_state([0.0, 0.25], [0.0, 0.0])
    np.testing.assert_allclose(sim.actuator_forces(), [3.0, 40.0 * 0.75], rtol=0, atol=1e-12)


def test_a_position_servo_holds_against_gravity_with_its_predicted_offset():
    sim = hopsim.Simulation(machine().scene())
    sim.set_control("hold", 0.5)
    sim.step(10000)
    # kp (ctrl − q) = m g l sin q, solved by bisection.
    lo, hi = 0.0, 0.5
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if 40.0 * (0.5 - mid) > M * G * L * math.sin(mid) else (lo, mid)
    assert sim.q[1] == pytest.approx(lo, abs=1e-9)


def test_a_control_signal_drives_its_actuator_in_the_scenes_steps():
    signal = {"kind": "sine", "amplitude": 0.4, "frequency": 2.0, "offset": 0.1}
    sim = hopsim.Simulation(machine(control=signal).scene())
    dt = sim.scene.dt
    for k in range(5):
        sim.step()
        t_mid = (k + 0.5) * dt
        expected = 0.1 + 0.4 * math.sin(2 * math.pi * 2.0 * t_mid)
        assert sim.control[0] == pytest.approx(expected, abs=1e-15)


def test_bad_controls_are_refused():
    sim = hopsim.Simulation(machine().scene())
    with pytest.raises(KeyError, match=r"no actuator named .*sping.*; the actuators are"):
        sim.set_control("sping", 1.0)
    with pytest.raises(IndexError):
        sim.set_control(2, 1.0)
    with pytest.raises(ValueError, match="not a finite number"):
        sim.set_control("spin", float("nan"))
    with pytest.raises(ValueError, match="3 controls given; the model has 2 actuators"):
        sim.control = [1.0, 2.0, 3.0]
    np.testing.assert_array_equal(sim.control, [0.0, 0.0])


def test_a_bad_actuator_names_its_call():
    model = machine()
    model.actuator("broken", joint="rod", kind="velocity")
    with pytest.raises(hopsim.SceneError, match="kv"):
        model.scene()
    with pytest.raises(TypeError, match="unknown keyword 'kpp'"):
        machine().actuator("x", joint="rod", kind="position", kpp=1.0)


ARM_XML = """\
<mujoco model="arm">
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="torque" joint="shoulder" gear="50" ctrllimited="true" ctrlrange="-1 1"/>
    <velocity name="speed" joint="shoulder" kv="3"/>
  </actuator>
</mujoco>
"""


def test_a_mujoco_models_actuators_are_the_scenes(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML)
    scene = hopsim.Scene.load(str(path))
    sim = hopsim.Simulation(scene)
    assert sim.actuator_names == ["torque", "speed"]
    sim.set_state([0.0], [2.0])
    # MuJoCo's qfrc_actuator: 50 · clamp(2, −1, 1) + 3 (0.5 − 2).
    sim.control = [2.0, 0.5]
    np.testing.assert_allclose(sim.actuator_forces(), [50.0 + 3.0 * (0.5 - 2.0)], rtol=1e-15)
    # The scene's model writes them back.
    assert "[[actuators]]" in scene.model.toml()
    assert hopsim.Simulation(scene.model.scene()).actuator_names == ["torque", "speed"]
