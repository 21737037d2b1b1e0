"""hopsim.Model: models built in code run as the scene files they write; errors name the
builder call and argument; Scene.model gives back the scene it came from."""

import ast
import keyword
import math
import pickle
import random
import re
import subprocess

import numpy as np
import pytest

import hopsim
from conftest import REPO, SCENES

#: Summary figures that are the machine's, not the run's.
TIMING = ("wall_time_s", "steps_per_s")


def without_timing(summary):
    return {k: v for k, v in summary.items() if k not in TIMING}


def assert_same_run(a, b, duration=None):
    """The two scenes run the same trajectory (bit for bit) and summary."""
    ta = hopsim.Simulation(a).run(duration)
    tb = hopsim.Simulation(b).run(duration)
    np.testing.assert_array_equal(ta.steps, tb.steps)
    np.testing.assert_array_equal(ta.q, tb.q)
    np.testing.assert_array_equal(ta.u, tb.u)
    assert ta.events == tb.events
    assert without_timing(ta.summary) == without_timing(tb.summary)
    return ta


def robbit_in_code():
    """scenes/robbit.toml written with the builder: Table 5.1 (docs/physics.md §5.3)."""
    return (
        hopsim.Model("Robbit")
        .simulation(duration=20.0, dt=2e-4, record_rate=1000.0)
        .summary(speed_window=10.0, cube_restitution=0.5)
        .environment(terrain="flat", friction=1.0, restitution=0.0)
        .body("disc", mass=0.974, inertia=3.004e-3)
        .body("flywheel", parent="disc", coordinate="absolute", coordinate_name="psi",
              mass=0.431, inertia=1.543e-3)
        .shape("disc", body="disc", type="circle", center=[0.0, 0.1], radius=0.2)
        .controller(type="momentum_impulse", flywheel="flywheel", torque=0.384,
                    impulse_limit=0.059, release="touchdown", rearm_timeout=1.0)
        .initial(q=[0.0, 0.1, 0.0, 0.0], u=np.zeros(4))
    )


def hopper_in_code(drop=0.2):
    """A 1 kg body on a sprung prismatic leg (1000 N/m, a stop at its rest length 0.5 m)
    with a 0.01 kg point foot `drop` m above the ground (docs/classics.md §2)."""
    return (
        hopsim.Model("hopper in code")
        .simulation(duration=1.0, dt=1e-5)
        .environment(friction=1.0, restitution=0.0)
        .body("body", mass=1.0, inertia=0.01)
        .body("foot", parent="body", joint="prismatic", axis=(0.0, -1.0), coordinate_name="s",
              mass=0.01, inertia=1e-6, stiffness=1000.0, rest_position=0.5, limits=[0.1, 0.5])
        .shape(body="foot", type="point", position=[0.0, 0.0])
        .shape("trunk", body="body", type="box", half_width=0.05, half_height=0.05)
        .initial(q=[0.0, 0.5 + drop, 0.0, 0.5])
    )


def test_robbit_in_code_runs_as_its_scene_file(robbit_path):
    model = robbit_in_code()
    scene = model.scene()
    assert scene.path == "<Model 'Robbit'>" and scene.title == "Robbit"
    assert scene.coordinates == ["x", "y", "phi", "psi"]
    file = hopsim.Scene.load(robbit_path)
    trajectory = assert_same_run(scene, file, duration=4.0)
    assert trajectory.summary["hops"] > 0  # flight and impacts are compared too
    assert any(e["kind"] == "brake" for e in trajectory.events)


def test_a_hopper_in_code_falls_freely_hops_and_is_recorded(hopsim_bin, tmp_path):
    model = hopper_in_code(drop=0.2)
    scene = model.scene()
    assert scene.coordinates == ["x", "y", "phi", "s"]
    trajectory = hopsim.Simulation(scene).run()
    # The leg rests on its stop, so the hopper falls as one body until the foot lands:
    # after sqrt(2 h / g) (within a step).
    touchdowns = [e["t_s"] for e in trajectory.events if e["kind"] == "touchdown"]
    # The contact is found at a step's midpoint and reported at its end: t* + Δt/2 at the
    # earliest, before t* + 3Δt/2 (Moreau's midpoint scheme is exact in free fall).
    late = touchdowns[0] - math.sqrt(2 * 0.2 / 9.81)
    assert scene.dt / 2 <= late < 1.5 * scene.dt
    assert trajectory.summary["hops"] >= 1

    path = tmp_path / "hopper.toml"
    path.write_text(model.toml())
    mcap = tmp_path / "hopper.mcap"
    subprocess.run([hopsim_bin, "run", str(path), "--quiet", "--mcap", str(mcap)], check=True)
    recording = hopsim.read_mcap(mcap)
    assert recording.scene_text == model.toml()
    assert recording.metadata["coordinates"] == scene.coordinates
    np.testing.assert_array_equal(recording.steps, trajectory.steps)
    np.testing.assert_array_equal(recording.q, trajectory.q)
    np.testing.assert_array_equal(recording.u, trajectory.u)


def test_a_capsule_is_given_with_from_and_lands_on_both_caps():
    """`from` is a Python keyword: the builder takes `from_` and writes `from`. A rod with
    round ends (a capsule 0.4 m long, 2 cm radius) dropped flat rests on both end caps."""
    model = (
        hopsim.Model("rod")
        .simulation(duration=0.5, dt=1e-3)
        .body("rod", mass=1.0, inertia=1.4e-2)
        .shape("rod", body="rod", type="capsule", from_=[-0.2, 0.0], to=[0.2, 0.0], radius=0.02)
        .initial(q=[0.0, 0.05, 0.0])
    )
    assert "from = [-0.2, 0.0]" in model.toml()
    sim = hopsim.Simulation(model.scene())
    sim.run()
    loaded = [c for c in sim.contacts() if c["impulse_normal"] > 0.0]
    assert len(loaded) == 2
    total = sum(c["impulse_normal"] for c in loaded)
    assert total == pytest.approx(9.81 * 1e-3, rel=1e-6)


def test_a_model_is_swept_like_a_scene():
    scene = hopper_in_code().scene()
    table = hopsim.sweep(scene, grid={"bodies.body.mass": [1.0, 2.0]})
    assert table["status"] == ["ok", "ok"]
    assert list(table["bodies.body.mass"]) == [1.0, 2.0]


def bundled_scenes():
    return sorted(SCENES.glob("**/*.toml"))


@pytest.mark.parametrize("path", bundled_scenes(), ids=lambda p: str(p.relative_to(SCENES)))
def test_every_bundled_scene_runs_as_its_model(path):
    file = hopsim.Scene.load(path)
    model = file.model
    assert isinstance(model, hopsim.Model) and model.title == file.title
    scene = model.scene()
    for attribute in ("title", "coordinates", "bodies", "shapes", "contacts", "settings",
                      "controller"):
        assert getattr(scene, attribute) == getattr(file, attribute), attribute
    np.testing.assert_array_equal(scene.initial_q, file.initial_q)
    np.testing.assert_array_equal(scene.initial_u, file.initial_u)
    # Long enough for every scene's first contacts, short enough for the test.
    assert_same_run(scene, file, duration=min(file.duration, 3000 * file.dt))


def test_bundled_scenes_are_found():
    names = {p.name for p in bundled_scenes()}
    assert {"robbit.toml", "canebot-timed.toml", "hopper.toml", "cradle-3.toml"} <= names


def reader_keys(model, path, overrides=None):
    """The keys the scene reader knows in the table at `path` (`bodies.1`) of `model`'s
    scene: those its "unknown key" error lists."""
    with pytest.raises(hopsim.SceneError) as info:
        model.scene(overrides={**(overrides or {}), f"{path}.not_a_key": 1})
    return set(re.search(r"known keys here: (.*)$", str(info.value)).group(1).split(", "))


def test_the_builder_knows_the_keys_the_scene_reader_knows():
    """Every table of every bundled scene, and the terrains and shapes no bundled scene
    uses: the builder's keywords are the reader's keys, no more and no fewer."""
    known = {s.table: set() for s in hopsim._model._SECTIONS if s.table != "meta"}
    for path in bundled_scenes():
        model = hopsim.Scene.load(path).model
        for table in known:
            if table in model._arrays:
                paths = [f"{table}.{i}" for i in range(len(model._arrays[table]))]
            else:
                paths = [table]
            for path in paths:
                known[table] |= reader_keys(model, path)
    robbit = robbit_in_code()
    for terrain in ({"environment.terrain": "incline", "environment.angle": 0.1},
                    {"environment.terrain": "step", "environment.step_x": 1.0,
                     "environment.step_height": 0.05}):
        known["environment"] |= reader_keys(robbit, "environment", terrain)
    # A capsule: no bundled scene has one.
    rod = (
        hopsim.Model("rod")
        .simulation(duration=1.0, dt=1e-3)
        .body("rod", mass=1.0, inertia=1e-2)
        .shape("rod", body="rod", type="capsule", from_=[-0.1, 0.0], to=[0.1, 0.0], radius=0.02)
    )
    known["shapes"] |= reader_keys(rod, "shapes.0")
    # A position servo asks every key of an actuator: no bundled scene has one.
    arm = (
        hopsim.Model("arm")
        .simulation(duration=1.0, dt=1e-3)
        .environment(terrain="none")
        .body("arm", base="pinned", mass=1.0, inertia=1e-2)
        .actuator("shoulder", joint="arm", kind="position", kp=1.0)
        .initial(q=[0.0])
    )
    known["actuators"] |= reader_keys(arm, "actuators.0")
    for table, keys in known.items():
        assert set(hopsim._model._BY_TABLE[table].keys) == keys, table


def test_the_model_of_a_scene_carries_its_overrides_and_changes_in_code(robbit_path):
    overridden = hopsim.Scene.load(robbit_path, overrides={"controller.torque": 0.2})
    model = overridden.model
    assert "torque = 0.2\n" in model.toml()
    assert_same_run(model.scene(), overridden, duration=2.0)

    model = hopsim.Scene.load(robbit_path).model
    model.body("flywheel", mass=0.5).simulation(duration=2.0)
    assert [b["mass"] for b in model.scene().bodies] == [0.974, 0.5]
    by_override = hopsim.Scene.load(
        robbit_path, overrides={"bodies.flywheel.mass": 0.5, "simulation.duration": 2.0}
    )
    assert_same_run(model.scene(), by_override)
    # None removes a key: the default comes back.
    model.simulation(record_rate=None)
    assert "record_rate" not in model.toml()
    assert model.scene().settings["record_rate"] == 1000.0
    # Overrides apply on top of the model.
    assert model.scene(overrides={"controller.torque": 0.3}).controller["torque"] == 0.3


def line_of(model, text):
    """The 1-based line of `model.toml()` that is `text`."""
    return model.toml().splitlines().index(text) + 1


def test_a_value_error_names_the_call_and_argument():
    model = robbit_in_code().body("leg", parent="disc", mass=-1, inertia=1e-4)
    with pytest.raises(hopsim.SceneError) as info:
        model.scene()
    e = info.value
    assert str(e) == (
        "Model.body('leg', mass=-1): mass: expected a positive number in kg, "
        "found the integer -1"
    )
    assert (e.call, e.argument) == ("Model.body('leg', mass=-1)", "mass")
    assert e.key == "bodies[2].mass"
    assert e.file == "<Model 'Robbit'>" and e.line == line_of(model, "mass = -1")
    assert e.override is None and isinstance(e, ValueError)


@pytest.mark.parametrize(
    "change, expected",
    [
        # A key that is missing names the call of its table.
        (lambda m: m.body("leg", parent="disc", inertia=1e-4),
         "Model.body('leg'): mass: missing in [bodies[2]]; expected a positive number in kg"),
        # A name that refers to nothing, with the scene reader's "did you mean".
        (lambda m: m.shape(body="dsic", type="point", position=[0, 0]),
         "Model.shape(body='dsic', type='point'): body: there is no body named 'dsic'; "
         "did you mean 'disc'?"),
        # A later call that changes a key is the one named.
        (lambda m: m.controller(impulse_limit=0.0),
         "Model.controller(impulse_limit=0.0): impulse_limit: expected a positive number in "
         "N m s, found the number 0"),
        # The start is checked against the terrain.
        (lambda m: m.initial(q=[0.0, 0.05, 0.0, 0.0]),
         "Model.initial(q=[0.0, 0.05, 0.0, 0.0]): q: the shape 'disc' starts 5.000000e-2 m "
         "inside the terrain"),
        (lambda m: m.environment(terrain="hilly"),
         "Model.environment(terrain='hilly'): terrain: expected one of"),
        (lambda m: m.spring(body_a="disc", body_b="flywheel", stiffness=10.0),
         "Model.spring(body_a='disc', body_b='flywheel'): rest_length: missing"),
        (lambda m: m.contact_pair(["disc", "disc"]),
         "Model.contact_pair(['disc', 'disc']): shapes:"),
        (lambda m: m.loop("pin", type="revolute", body_a="disc", body_b="flywhel"),
         "Model.loop('pin', body_b='flywhel'): body_b: there is no body named 'flywhel'"),
        (lambda m: m.simulation(dt=math.nan),
         "Model.simulation(dt=nan): dt: expected a positive number in s"),
    ],
)
def test_value_errors_of_every_table_are_located(change, expected):
    model = robbit_in_code()
    change(model)
    with pytest.raises(hopsim.SceneError) as info:
        model.scene()
    assert str(info.value).startswith(expected), str(info.value)


def test_a_table_never_written_is_named_with_the_model():
    model = hopsim.Model("bare").body("b", mass=1.0, inertia=1.0).initial(q=[0, 1, 0])
    with pytest.raises(hopsim.SceneError) as info:
        model.scene()
    expected = "Model('bare'): simulation.duration: missing"
    assert str(info.value).startswith(expected), str(info.value)


@pytest.mark.parametrize(
    "call, expected",
    [
        (lambda m: m.body("leg", mas=1.0),
         "Model.body('leg'): unknown keyword 'mas'; did you mean 'mass'?"),
        (lambda m: m.body("leg", radius=0.1),
         "Model.body('leg'): unknown keyword 'radius' (a key of Model.shape); the keys of "
         "[bodies] are name, mass,"),
        (lambda m: m.simulation(durration=1.0),
         "Model.simulation(): unknown keyword 'durration'; did you mean 'duration'?"),
        (lambda m: m.body("leg", mass="heavy"),
         "Model.body('leg', mass='heavy'): mass: expected a number, got str 'heavy'"),
        (lambda m: m.body("leg", mass=True),
         "Model.body('leg', mass=True): mass: expected a number, got bool True"),
        (lambda m: m.body(3, mass=1.0),
         "Model.body(3): name: expected a string, got int 3"),
        (lambda m: m.shape(body="disc", type="circle", center=[0.0, "up"]),
         "Model.shape(body='disc', type='circle', center=[0.0, 'up']): center: expected a "
         "pair of numbers [x, y], got list"),
        (lambda m: m.shape(body="disc", type="polygon", vertices=[[0, 0], [1, 0], 5]),
         "Model.shape(body='disc', type='polygon', vertices=[[0, 0], [1, 0], 5]): vertices: "
         "expected a sequence of [x, y] pairs"),
        (lambda m: m.initial(q="0 0.1 0 0"),
         "Model.initial(q='0 0.1 0 0'): q: expected a sequence of numbers, got str"),
        (lambda m: m.controller(hold_brake=1),
         "Model.controller(hold_brake=1): hold_brake: expected True or False, got int 1"),
        (lambda m: m.contact_pair(["disc", 2]),
         "Model.contact_pair(['disc', 2]): shapes: expected a sequence of strings"),
        (lambda m: m.meta(author=object),
         "Model.meta(author=<class 'object'>): author: expected a string, number, bool"),
    ],
)
def test_python_type_and_keyword_errors_are_raised_at_the_call(call, expected):
    model = robbit_in_code()
    before = model.toml()
    with pytest.raises(TypeError) as info:
        call(model)
    assert str(info.value).startswith(expected), str(info.value)
    assert model.toml() == before  # a refused call changes nothing


@pytest.mark.parametrize(
    "call, expected",
    [
        (lambda m: m.body("leg", mass=2**64),
         "Model.body('leg', mass=18446744073709551616): mass: the integer "
         "18446744073709551616 does not fit in 64 bits"),
        (lambda m: m.meta(notes="half \ud800 a pair"),
         "Model.meta(notes='half \\ud800 a pair'): notes: the text 'half \\ud800 a pair' is "
         "not Unicode (surrogates not allowed)"),
    ],
)
def test_values_no_scene_file_can_hold_are_refused_at_the_call(call, expected):
    with pytest.raises(hopsim.SceneError) as info:
        call(robbit_in_code())
    assert str(info.value) == expected
    assert info.value.call == expected.split(": ")[0]


def test_odd_python_values_are_type_errors():
    model = robbit_in_code()
    for call in (
        lambda: model.body("leg", pivot=np.array(1.0)),  # a 0-d array is no pair
        lambda: model.meta(title=None),  # a model keeps its title
        lambda: hopsim.Model(None),
        lambda: model.initial(q=(x for x in range(4))),  # a generator has no length
    ):
        with pytest.raises(TypeError) as info:
            call()
        assert str(info.value).startswith("Model"), str(info.value)


def test_a_model_pickles():
    model = robbit_in_code()
    copy = pickle.loads(pickle.dumps(model))
    assert copy.toml() == model.toml()
    copy.body("disc", mass=-1.0)  # the copy's calls are its own
    with pytest.raises(hopsim.SceneError, match=r"^Model.body\('disc', mass=-1.0\): mass:"):
        copy.scene()
    assert model.scene().bodies[0]["mass"] == 0.974


def test_an_override_error_names_the_override():
    with pytest.raises(hopsim.SceneError) as info:
        robbit_in_code().scene(overrides={"controller.torque": "fast"})
    e = info.value
    assert e.override == "overrides (controller.torque=fast)"
    assert str(e).startswith("overrides (controller.torque=fast): controller.torque:")


def test_text_and_numbers_are_written_exactly():
    awkward = 'quote " backslash \\ tab \t newline \n bell \x07 del \x7f é 🦘'
    numbers = [0.1, 1 / 3, 5e-324, 1.7976931348623157e308, -0.0, 123456789.125]
    model = robbit_in_code().meta(notes=awkward, values=numbers, nested={"a key": [1, True]})
    scene = model.scene()
    document = scene.model  # read back by the scene reader
    notes = re.search(r"^notes = (.*)$", document.toml(), re.M).group(1)
    assert notes == re.search(r"^notes = (.*)$", model.toml(), re.M).group(1)
    assert sorted(document.toml().splitlines()) == sorted(model.toml().splitlines())
    for x in numbers:
        assert repr(x) in model.toml()


def test_numpy_values_are_accepted():
    model = robbit_in_code()
    model.body("extra", parent="disc", mass=np.float32(0.25), inertia=np.float64(1e-4),
               pivot=np.array([0.0, 0.05]), limits=(np.int64(-1), 1))
    model.initial(q=np.array([0.0, 0.1, 0.0, 0.0, 0.0]), u=np.zeros(5))
    scene = model.scene()
    assert scene.bodies[2]["mass"] == 0.25


#: Values a generated key may take, by the kind of the key: mostly sensible, some out of
#: range, of the wrong length or not finite.
POOLS = {
    hopsim._model.NUMBER: [0.0, 1.0, -1.0, 0.2, 1e-3, 2, 10**12, math.nan, math.inf],
    hopsim._model.STRING: ["b0", "b1", "disc", "", "relative", "absolute", "prismatic",
                           "pinned", "fixed", "floating"],
    hopsim._model.BOOL: [True, False],
    hopsim._model.VEC2: [[0.0, 0.0], [0.1, -0.2], [0.0, -1.0], [-0.5, 0.5], [1.0], []],
    hopsim._model.NUMBERS: [[0, 1], [0.0, 0.5, 1.0], []],
    hopsim._model.POINTS: [[[0, 0], [1, 0], [0, 1]], [[0, 0], [0, 1], [1, 0]], [[0, 0]]],
    hopsim._model.NAMES: [["b0", "b1"]],
}
#: A valid shape of each type (and a type that does not exist).
GEOMETRY = {
    "circle": {"radius": 0.1},
    "arc": {"radius": 0.1, "start": 0.0, "end": 3.0},
    "ellipse": {"semi_x": 0.1, "semi_y": 0.05},
    "point": {"position": [0.0, -0.1]},
    "polygon": {"vertices": [[0, 0], [0.1, 0], [0, 0.1]]},
    "box": {"half_width": 0.1, "half_height": 0.05},
    "blob": {},
}
#: Values of another type, and misspelt or misplaced keywords.
WRONG = ["text", None, {"a": 1}, [0.0, "x"], 10**30]
MISTAKES = ["mas", "radius", "radus", "parnet"]


def random_keys(rng, table, count):
    keys = {}
    known = hopsim._model._BY_TABLE[table].keys
    for key in rng.sample(list(known), count):
        kind = known[key][0]
        keys[key] = rng.choice(WRONG) if rng.random() < 0.03 else rng.choice(POOLS[kind])
    if rng.random() < 0.03:
        keys[rng.choice(MISTAKES)] = 1.0
    keys.pop("name", None)
    return keys


def random_model(rng):
    """A model of a few bodies and shapes with keys drawn at random."""
    model = hopsim.Model("generated").simulation(duration=0.01, dt=1e-3)
    names = ["b0"]
    model.body("b0", mass=1.0, inertia=0.1)
    for i in range(rng.randint(0, 3)):
        keys = {"parent": rng.choice(names), "mass": rng.uniform(0.1, 2), "inertia": 0.01}
        keys.update(random_keys(rng, "bodies", rng.randint(0, 2)))
        names.append(f"b{i + 1}")
        model.body(names[-1], **keys)
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(list(GEOMETRY))
        keys = {"body": rng.choice(names), "type": kind, **GEOMETRY[kind]}
        keys.update(random_keys(rng, "shapes", rng.randint(0, 2)))
        model.shape(**keys)
    model.initial(q=[rng.uniform(-1, 1) for _ in range(3 + len(names) - 1)],
                  rest_on_ground=rng.random() < 0.7)
    return model


def test_generated_models_give_a_scene_or_a_located_error():
    rng = random.Random(20261127)
    outcomes = {"scene": 0, "TypeError": 0, "SceneError": 0}
    for _ in range(400):
        try:
            scene = random_model(rng).scene()
        except TypeError as error:
            assert str(error).startswith("Model."), str(error)
            outcomes["TypeError"] += 1
        except hopsim.SceneError as error:
            assert re.match(r"^Model(\.\w+)?\(", str(error)), str(error)
            outcomes["SceneError"] += 1
        else:
            try:
                hopsim.Simulation(scene).step(5)
            except hopsim.SimulationError:
                pass
            outcomes["scene"] += 1
    # The loop exercises every outcome.
    assert min(outcomes.values()) >= 20, outcomes


def models_in_code_example():
    """The first Python block of docs/python.md's "Models in code"."""
    text = (REPO / "docs" / "python.md").read_text()
    section = text.split("### Models in code", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_documented_example_runs(monkeypatch, capsys):
    monkeypatch.chdir(REPO)
    namespace = {}
    exec(compile(models_in_code_example(), "docs/python.md", "exec"), namespace)
    assert namespace["trajectory"].summary["hops"] >= 1
    assert namespace["table"]["status"] == ["ok", "ok"]
    example = models_in_code_example()
    documented = re.search(r"# (Model\.body\('leg2'.*)$", example, re.M).group(1)
    assert namespace["message"] == documented
    assert capsys.readouterr().out


def test_the_type_stub_has_every_keyword():
    """python/hopsim/_model.pyi, for type checkers: one keyword per key of each table."""
    stub = ast.parse((REPO / "python" / "hopsim" / "_model.pyi").read_text())
    model = next(n for n in stub.body if isinstance(n, ast.ClassDef) and n.name == "Model")
    methods = {f.name: f.args for f in model.body if isinstance(f, ast.FunctionDef)}
    for section in hopsim._model._SECTIONS:
        args = methods[section.method]
        names = [a.arg for a in args.args[1:] + args.kwonlyargs]
        # A key that is a Python keyword (a capsule's `from`) is the keyword `from_`.
        names = [n[:-1] if n.endswith("_") and keyword.iskeyword(n[:-1]) else n for n in names]
        assert sorted(names) == sorted(section.keys), section.method
