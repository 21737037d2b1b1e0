"""Scenes: loading, overrides, located errors, pickling."""

import pickle
import sys

import numpy as np
import pytest

import hopsim

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.9 and 3.10: the same parser, from PyPI
    tomllib = pytest.importorskip("tomli")

SMALL = """\
[meta]
title = "ball"

[simulation]
duration = 0.5
dt = 1e-3

[[bodies]]
name = "ball"
mass = 1.0
inertia = 0.01

[[shapes]]
name = "ball"
body = "ball"
type = "circle"
radius = 0.1

[initial]
q = [0.0, 0.5, 0.0]
"""


def test_load_reads_the_scene(robbit, robbit_path):
    assert robbit.title == "Robbit"
    assert robbit.path == str(robbit_path)
    assert robbit.coordinates == ["x", "y", "phi", "psi"]
    assert [b["name"] for b in robbit.bodies] == ["disc", "flywheel"]
    assert robbit.bodies[1]["parent"] == 0
    assert robbit.duration == 2.0
    assert robbit.dt == 2e-4
    # The controller as the file states it, read here with a TOML parser of Python's own.
    with open(robbit_path, "rb") as f:
        stated = tomllib.load(f)["controller"]
    assert robbit.controller["type"] == stated["type"] == "momentum_impulse"
    assert robbit.controller["torque"] == stated["torque"]
    assert robbit.controller["impulse_limit"] == stated["impulse_limit"]
    assert robbit.controller["release"] == stated.get("release", "touchdown")
    np.testing.assert_array_equal(robbit.initial_q, [0.0, 0.1, 0.0, 0.0])
    assert robbit.body_index("flywheel") == 1


def test_overrides_take_python_values(robbit):
    s = robbit.with_overrides({"controller.torque": 0.2, "controller.hold_brake": True})
    assert s.controller["torque"] == 0.2
    assert s.controller["hold_brake"] is True
    assert s.duration == 2.0  # the scene's own overrides stay
    listed = robbit.with_overrides({"initial.q": [0.0, 0.2, 0.0, 0]})
    np.testing.assert_array_equal(listed.initial_q, [0.0, 0.2, 0.0, 0.0])


def test_syntax_error_is_located():
    bad = SMALL.replace("mass = 1.0", "mass = = 1.0")
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.from_toml(bad, path="ball.toml")
    e = info.value
    assert isinstance(e, ValueError)
    assert e.file == "ball.toml"
    assert e.line == 10
    assert e.column is not None and e.column >= 1
    assert "ball.toml:10:" in str(e)


def test_invalid_value_names_file_line_column_and_key():
    bad = SMALL.replace("mass = 1.0", "mass = -1.0")
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.from_toml(bad, path="ball.toml")
    e = info.value
    assert (e.file, e.line, e.column) == ("ball.toml", 10, 8)
    assert e.key == "bodies[0].mass"
    assert e.override is None
    assert e.message in str(e)


def test_invalid_override_names_the_override():
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.from_toml(SMALL, overrides={"bodies.ball.mass": "heavy"})
    e = info.value
    assert e.key == "bodies[0].mass"
    assert e.override is not None and "bodies.ball.mass=heavy" in e.override
    assert e.line is None


def test_unknown_key_suggests_the_right_one():
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.from_toml(SMALL.replace("dt = 1e-3", "dtt = 1e-3"))
    assert "dt" in str(info.value)


def test_missing_file_is_a_scene_error(tmp_path):
    missing = tmp_path / "none.toml"
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.load(missing)
    assert info.value.file == str(missing)


def test_override_of_unsupported_type_is_a_type_error():
    with pytest.raises(TypeError):
        hopsim.Scene.from_toml(SMALL, overrides={"simulation.dt": object()})


def test_scene_pickles_with_its_overrides(robbit):
    s = robbit.with_overrides({"controller.torque": 0.2})
    back = pickle.loads(pickle.dumps(s))
    assert back.text == s.text and back.path == s.path
    assert back.controller == s.controller
    assert back.overrides == s.overrides


PENDULUM_XML = """\
<mujoco model="pendulum">
  <worldbody>
    <body name="pole" pos="0 0 1">
      <joint name="swing" type="hinge" axis="0 1 0" ref="30"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="2"/>
    </body>
  </worldbody>
  <actuator><motor joint="swing"/></actuator>
</mujoco>
"""


def test_load_imports_a_mujoco_model(tmp_path):
    path = tmp_path / "pendulum.xml"
    path.write_text(PENDULUM_XML)
    scene = hopsim.Scene.load(str(path), overrides={"simulation.duration": 0.2})
    assert scene.title == "pendulum"
    assert scene.path == str(path)
    # MuJoCo's qpos, named by the joint, in radians with its ref.
    assert scene.coordinates == ["swing"]
    np.testing.assert_allclose(scene.initial_q, [np.radians(30.0)], rtol=0, atol=1e-15)
    assert [b["name"] for b in scene.bodies] == ["world", "pole"]
    assert not any("actuator" in n for n in scene.notices)
    assert hopsim.Simulation(scene).actuator_names == ["actuator0"]
    assert scene.duration == 0.2
    # Released at its ref it hangs still: gravity has no torque there.
    sim = hopsim.Simulation(scene)
    sim.step(10)
    np.testing.assert_allclose(sim.q, [np.radians(30.0)], rtol=0, atol=1e-12)
    # And as any scene it is picklable, with its notices.
    again = pickle.loads(pickle.dumps(scene))
    assert again.notices == scene.notices


def test_a_model_outside_the_subset_is_a_located_scene_error(tmp_path):
    path = tmp_path / "free.xml"
    path.write_text(PENDULUM_XML.replace('type="hinge" axis="0 1 0"', 'type="free"'))
    with pytest.raises(hopsim.SceneError) as info:
        hopsim.Scene.load(str(path))
    assert f"{path}:4:" in str(info.value)
