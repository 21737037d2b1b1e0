"""Models built in code: :class:`Model`, a builder with the vocabulary of the scene format
(docs/scene-format.md) that writes a scene's TOML and reads it back with the scene reader,
so that a model in code is checked exactly as a file is and runs as the same file would.

Python types and keyword names are checked at each call; values (ranges, names that must
exist, shapes in the ground at the start, …) by the scene reader in :meth:`Model.scene`,
whose errors are mapped back to the call and argument that wrote the value.
"""

from __future__ import annotations

import difflib
import keyword
import math
import numbers
import re
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ._hopsim import Scene, SceneError

# Kinds of values a key takes (checked in Python; values are checked by the scene reader).
NUMBER = "a number"
STRING = "a string"
BOOL = "True or False"
VEC2 = "a pair of numbers [x, y]"
NUMBERS = "a sequence of numbers"
POINTS = "a sequence of [x, y] pairs"
NAMES = "a sequence of strings"
VALUE = "a string, number, bool, or a list or dict of these"

_MATERIAL = (
    ("friction", NUMBER, "Coulomb μ, ≥ 0"),
    ("restitution", NUMBER, "normal restitution ε_N, in [0, 1]"),
    ("tangential_restitution", NUMBER, "tangential restitution ε_T, in [−1, 1]"),
)


class _Section:
    """One table of the scene format: its TOML name, whether it is an array of tables, the
    builder method that writes it, and its keys as ``(key, kind, meaning)``."""

    def __init__(
        self, table: str, method: str, many: bool, keys: Sequence[Tuple[str, str, str]]
    ):
        self.table, self.method, self.many = table, method, many
        self.keys: Dict[str, Tuple[str, str]] = {k: (kind, doc) for k, kind, doc in keys}

    def doc(self) -> str:
        """The keys as a docstring's list."""
        return "\n".join(f"* ``{k}`` ({kind}): {doc}" for k, (kind, doc) in self.keys.items())


_SECTIONS: Tuple[_Section, ...] = (
    _Section("meta", "meta", False, (
        ("title", STRING, "shown in summaries, plots and viewers"),
        ("source", STRING, "where the parameters come from"),
        ("notes", STRING, "rationale, remarks"),
    )),
    _Section("simulation", "simulation", False, (
        ("duration", NUMBER, "simulated time, s; required, > 0"),
        ("dt", NUMBER, "step size Δt, s; required, > 0 and < duration"),
        ("gravity", NUMBER, "gravitational acceleration along −y, m/s² (9.81)"),
        ("gravity_x", NUMBER, "gravitational acceleration along +x, m/s² (0)"),
        ("record_rate", NUMBER, "frames per simulated second in recordings, Hz (1000)"),
        ("strict", BOOL, "stop on the first contact LCP without a certified solution (False)"),
        ("warm_start", BOOL, "solve each contact LCP first from the last basis (True)"),
        ("max_speed", NUMBER, "a velocity above this stops the run, m/s or rad/s (1e4)"),
        ("max_steps", NUMBER, "the most steps duration / dt may take (1e8)"),
    )),
    _Section("summary", "summary", False, (
        ("speed_window", NUMBER, "mean speed etc. over the last this many seconds, s"),
        ("cube_restitution", NUMBER, "restitution of the second cube baseline (0.5)"),
    )),
    _Section("environment", "environment", False, (
        ("terrain", STRING, '"flat" (default), "incline", "step" or "none"'),
        ("height", NUMBER, "flat: the ground is y = height, m (0)"),
        ("angle", NUMBER, "incline: the plane through the origin rising towards +x, rad"),
        ("step_x", NUMBER, "step: x of the step's face, m"),
        ("step_height", NUMBER, "step: the step's height, m"),
    ) + _MATERIAL),
    _Section("bodies", "body", True, (
        ("name", STRING, "unique; required"),
        ("mass", NUMBER, "kg; required, > 0 (a fixed base: ≥ 0, default 0)"),
        ("inertia", NUMBER, "about the centre of mass, kg m²; required, > 0 (fixed: ≥ 0)"),
        ("parent", STRING, "the body this one hangs on"),
        ("base", STRING, 'a body without parent: "floating", "pinned" (at pivot) or "fixed"'),
        ("joint", STRING, 'the joint to the parent: "revolute" (default) or "prismatic"'),
        ("axis", VEC2, "a prismatic joint's direction in the parent's frame"),
        ("pivot", VEC2, "the joint in the parent's frame (a pinned base: world point), m"),
        ("com", VEC2, "this body's centre of mass relative to the joint, own frame, m"),
        ("coordinate", STRING, 'a revolute joint: "relative" (default), "clockwise" or "absolute"'),
        ("coordinate_name", STRING, "the coordinate's name in recordings and CSV"),
        ("damping", NUMBER, "viscous joint damping, N m s/rad or N s/m (0)"),
        ("armature", NUMBER, "added to the mass matrix at the joint's coordinate, kg m² or kg (0)"),
        ("dry_friction", NUMBER, "Coulomb friction in the joint: the largest torque or force it transmits, N m or N (0)"),
        ("stiffness", NUMBER, "joint spring, N m/rad or N/m (0)"),
        ("rest_position", NUMBER, "the joint spring's rest position, rad or m (0)"),
        ("limits", VEC2, "[lower, upper] end stops of the joint position, rad or m"),
        ("limit_restitution", NUMBER, "Newton restitution of both stops, in [0, 1] (0)"),
        ("position", VEC2, "a fixed base's centre of mass in the world, m"),
        ("angle", NUMBER, "a fixed base's angle, rad"),
    )),
    _Section("shapes", "shape", True, (
        ("body", STRING, "the body carrying the shape; required"),
        ("type", STRING, '"circle", "arc", "ellipse", "point", "polygon", "box" or "capsule"; required'),
        ("name", STRING, "unique (default <body>_<type>)"),
    ) + _MATERIAL + (
        ("switchable", BOOL, "switched by the controller (a cane); starts off (False)"),
        ("group", NUMBER, "collision group, a whole number 0–31 (0)"),
        ("collides_with", NUMBERS, "the groups this shape may touch (every group)"),
        ("center", VEC2, "circle, arc, ellipse, box: centre in the body frame, m"),
        ("radius", NUMBER, "circle, arc: m, > 0"),
        ("start", NUMBER, "arc: start angle, rad"),
        ("end", NUMBER, "arc: end angle, rad, 0 < end − start ≤ 2π"),
        ("semi_x", NUMBER, "ellipse: semi-axis along the body's x, m"),
        ("semi_y", NUMBER, "ellipse: semi-axis along the body's y, m"),
        ("position", VEC2, "point: the point in the body frame, m"),
        ("vertices", POINTS, "polygon: convex, counter-clockwise, at least 3, m"),
        ("half_width", NUMBER, "box: m"),
        ("half_height", NUMBER, "box: m"),
        ("from", VEC2, "capsule: one end of its segment in the body frame, m (keyword from_)"),
        ("to", VEC2, "capsule: the other end, m"),
    )),
    _Section("springs", "spring", True, (
        ("name", STRING, "default spring<i>"),
        ("body_a", STRING, "required"),
        ("body_b", STRING, "required, another body"),
        ("point_a", VEC2, "attachment in body_a's frame, m ([0, 0])"),
        ("point_b", VEC2, "attachment in body_b's frame, m ([0, 0])"),
        ("stiffness", NUMBER, "k, N/m; required, ≥ 0"),
        ("rest_length", NUMBER, "L0, m; required, ≥ 0"),
        ("damping", NUMBER, "force −c dL/dt along the spring, N s/m (0)"),
        ("tension_only", BOOL, "pulls only when longer than L0 (False)"),
    )),
    _Section("body_contacts", "body_contacts", False, (
        ("all", BOOL, "every two shapes of different bodies touch (False)"),
    ) + _MATERIAL),
    _Section("contact_pairs", "contact_pair", True, (
        ("shapes", NAMES, "the two shapes, on different bodies; required"),
    ) + _MATERIAL),
    _Section("loops", "loop", True, (
        ("name", STRING, "default loop<i>"),
        ("type", STRING, '"revolute", "distance", "weld" or "slot"; required'),
        ("body_a", STRING, "required"),
        ("point_a", VEC2, "the point in body_a's frame, m ([0, 0])"),
        ("body_b", STRING, 'another body or "world" ("world")'),
        ("point_b", VEC2, "the point in body_b's frame (the world's), m ([0, 0])"),
        ("length", NUMBER, "distance: the rod's length, m, > 0"),
        ("angle", NUMBER, "weld: θ_A − θ_B held, rad (0)"),
        ("axis", VEC2, "slot: the line's direction in body_b's frame"),
    )),
    _Section("controller", "controller", False, (
        ("type", STRING, '"passive" (default), "momentum_impulse" or "pulse"'),
        ("flywheel", STRING, "momentum_impulse: the flywheel body"),
        ("torque", NUMBER, "momentum_impulse: stance torque; pulse: the pulse's torque, N m"),
        ("impulse_limit", NUMBER, "momentum_impulse: ζ0, N m s, > 0"),
        ("release", STRING, 'momentum_impulse: "touchdown" (default) or "off_time"'),
        ("rearm_timeout", NUMBER, 'release = "touchdown": s (1.0)'),
        ("off_time", NUMBER, 'release = "off_time": motor off after each brake, s'),
        ("hold_brake", BOOL, "the brake stays engaged until the next cycle (False)"),
        ("joint", STRING, "pulse: the body driven against its parent"),
        ("force", NUMBER, "pulse on a prismatic joint: N"),
        ("pulse_duration", NUMBER, "pulse: length of each of the two pulses, s"),
        ("period", NUMBER, "pulse: motor period, s (or frequency)"),
        ("frequency", NUMBER, "pulse: motor frequency, Hz (or period)"),
        ("cane", STRING, "pulse: a switchable shape, the cane"),
        ("cane_mode", STRING, '"retracted" (default), "extended" or "timed"'),
        ("cane_delay", NUMBER, "timed: fraction of the period"),
        ("cane_duration", NUMBER, "timed: fraction of the period"),
        ("cane_schedule", STRING, 'timed: "windowed" (default) or "thesis" (the trigger)'),
    )),
    _Section("actuators", "actuator", True, (
        ("name", STRING, "unique (default actuator<i>); its control's name"),
        ("joint", STRING, "the body whose joint it drives; required"),
        ("kind", STRING, '"motor", "position" or "velocity"; required'),
        ("gear", NUMBER, "length gear · s, generalised force gear · force (1)"),
        ("kp", NUMBER, "position: force kp (ctrl − gear s), ≥ 0; required"),
        ("kv", NUMBER, "position: damping −kv gear ṡ (0); velocity: kv (ctrl − gear ṡ); ≥ 0"),
        ("ctrl_range", VEC2, "[lower, upper]: the control is clamped to it"),
        ("force_range", VEC2, "[lower, upper]: the force is clamped to it, N m or N"),
        ("control", VALUE, 'the control signal, a dict: {"kind": "constant", "sine", "pulse", '
                           '"table" or "csv", …} (docs/scene-format.md)'),
    )),
    _Section("initial", "initial", False, (
        ("q", NUMBERS, "one value per coordinate, m or rad; required"),
        ("u", NUMBERS, "generalised velocities, m/s or rad/s (zeros)"),
        ("rest_on_ground", BOOL, "lower the first tree onto the terrain (False)"),
    )),
)

_BY_TABLE: Dict[str, _Section] = {s.table: s for s in _SECTIONS}
_BY_METHOD: Dict[str, _Section] = {s.method: s for s in _SECTIONS}

#: Most characters of a value quoted in an error message.
_SHOWN = 60


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= _SHOWN else text[: _SHOWN - 1] + "…"


class _Call:
    """One builder call, named in errors by its method, what identifies the table it
    writes (a positional argument ``lead``, keys ``shown``) and the argument at fault:
    ``Model.body('leg', mass=-1)``, ``Model.shape(body='foot', type='point')``."""

    __slots__ = ("method", "given", "lead", "shown")

    def __init__(
        self,
        method: str,
        given: Mapping[str, Any],
        lead: Optional[str] = None,
        shown: Sequence[str] = (),
    ):
        self.method, self.given = method, dict(given)
        self.lead, self.shown = lead, tuple(k for k in shown if k in self.given)

    def text(self, key: Optional[str] = None) -> str:
        args = [_shown(self.given[self.lead])] if self.lead else []
        args += [f"{k}={_shown(self.given[k])}" for k in self.shown]
        if key in self.given and key != self.lead and key not in self.shown:
            args.append(f"{key}={_shown(self.given[key])}")
        name = f"Model.{self.method}" if self.method else "Model"
        return f"{name}({', '.join(args)})"


class _Item:
    """The keys of one table, each with the call that wrote it, and the call that
    started the table."""

    __slots__ = ("call", "keys")

    def __init__(self, call: _Call):
        self.call = call
        self.keys: Dict[str, Tuple[Any, _Call]] = {}


def _is_number(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _is_sequence(v: Any) -> bool:
    """A list, tuple, numpy array (not a 0-d one) or other sized iterable, not text."""
    if isinstance(v, (str, bytes, Mapping)) or not hasattr(v, "__iter__"):
        return False
    try:
        len(v)
    except TypeError:
        return False
    return True


def _plain(value: Any, kind: str) -> Any:
    """``value`` as plain Python (int, float, str, bool, lists, dicts) if it is of
    ``kind``, else ``None``."""
    if kind == NUMBER:
        if not _is_number(value):
            return None
        return int(value) if isinstance(value, numbers.Integral) else float(value)
    if kind == STRING:
        return str(value) if isinstance(value, str) else None
    if kind == BOOL:
        return bool(value) if isinstance(value, (bool, np.bool_)) else None
    if kind in (VEC2, NUMBERS, NAMES, POINTS):
        if not _is_sequence(value):
            return None
        inner = {VEC2: NUMBER, NUMBERS: NUMBER, NAMES: STRING, POINTS: VEC2}[kind]
        items = [_plain(v, inner) for v in value]
        return None if any(i is None for i in items) else items
    # VALUE: free-form [meta] entries.
    for simple in (BOOL, NUMBER, STRING):
        plain = _plain(value, simple)
        if plain is not None:
            return plain
    if isinstance(value, Mapping):
        items = {k: _plain(v, VALUE) for k, v in value.items()}
        ok = all(isinstance(k, str) for k in items) and None not in items.values()
        return items if ok else None
    if _is_sequence(value):
        items = [_plain(v, VALUE) for v in value]
        return None if any(i is None for i in items) else items
    return None


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_string(s: str) -> str:
    out = []
    for ch in s:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_key(key: str) -> str:
    return key if _BARE_KEY.match(key) else _toml_string(key)


def _toml(value: Any) -> str:
    """A plain Python value as TOML text (floats as the shortest text that reads back as
    the same double)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml(v)}" for k, v in value.items()) + " }"
    return "[" + ", ".join(_toml(v) for v in value) + "]"


_KEY_PATH = re.compile(
    r"^(?P<table>\w+)(?:\[(?P<index>\d+)\])?(?:\.(?P<key>\w+))?(?P<rest>.*)$"
)

#: Largest magnitude of a TOML integer.
_MAX_INT = 2**63 - 1


class Model:
    """A model built in code with the scene format's tables and keys (docs/scene-format.md,
    SI units): ``environment(...)``, ``body(name, ...)``, ``shape(...)``, ``spring(...)``,
    ``body_contacts(...)``, ``contact_pair(shapes, ...)``, ``controller(...)``,
    ``initial(q=..., u=...)``, ``simulation(duration=..., dt=...)``, ``summary(...)``,
    ``meta(...)``; each keyword is the TOML key of the same name, and each call returns the
    model (calls chain).

    ``toml()`` is the scene's text and ``scene(overrides=None)`` the :class:`Scene` it
    makes, validated as a file is (its path ``<Model 'title'>``): simulate, record and sweep
    it like any scene. A wrong Python type or an unknown keyword raises ``TypeError`` at the
    call; a value the scene reader refuses raises :class:`SceneError` from ``scene()``,
    naming the call and argument that wrote it (``Model.body('leg', mass=-1): mass:
    expected a positive number in kg, found the integer -1``), with ``call`` and
    ``argument`` attributes besides those of every ``SceneError``.

    A table's method called again sets the keys it is given and keeps the others; the
    value ``None`` removes a key. ``body``, ``shape`` and ``spring`` with the name of an
    existing one, and ``contact_pair`` with the shapes of an existing pair, change that
    one in the same way. ``Scene.model`` gives the model of a scene.
    """

    def __init__(self, title: str = "model", **meta: Any):
        self._tables: Dict[str, _Item] = {}
        self._arrays: Dict[str, List[_Item]] = {s.table: [] for s in _SECTIONS if s.many}
        given = {"title": title}
        self._set(_BY_TABLE["meta"], given, _Call("", given, lead="title"))
        if meta:
            self.meta(**meta)

    # Tables written once (a later call changes their keys).

    def meta(self, **keys: Any) -> "Model":
        self._set(_BY_TABLE["meta"], keys, _Call("meta", keys), free=True)
        return self

    def simulation(self, **keys: Any) -> "Model":
        return self._table("simulation", keys)

    def summary(self, **keys: Any) -> "Model":
        return self._table("summary", keys)

    def environment(self, **keys: Any) -> "Model":
        return self._table("environment", keys)

    def body_contacts(self, **keys: Any) -> "Model":
        return self._table("body_contacts", keys)

    def controller(self, **keys: Any) -> "Model":
        return self._table("controller", keys)

    def initial(self, **keys: Any) -> "Model":
        return self._table("initial", keys)

    # Arrays of tables (one call per body, shape, spring, pair or loop).

    def body(self, name: str, **keys: Any) -> "Model":
        return self._entry(_Call("body", {"name": name, **keys}, lead="name"))

    def shape(self, name: Optional[str] = None, **keys: Any) -> "Model":
        return self._named("shape", name, keys, ("body", "type"))

    def spring(self, name: Optional[str] = None, **keys: Any) -> "Model":
        return self._named("spring", name, keys, ("body_a", "body_b"))

    def contact_pair(self, shapes: Sequence[str], **keys: Any) -> "Model":
        return self._entry(_Call("contact_pair", {"shapes": shapes, **keys}, lead="shapes"))

    def loop(self, name: Optional[str] = None, **keys: Any) -> "Model":
        return self._named("loop", name, keys, ("type", "body_a"))

    def actuator(self, name: Optional[str] = None, **keys: Any) -> "Model":
        return self._named("actuator", name, keys, ("joint", "kind"))

    # The scene.

    @property
    def title(self) -> str:
        """``meta.title``."""
        return self._tables["meta"].keys["title"][0]

    def toml(self) -> str:
        """The scene file this model writes."""
        return self._render()[0]

    def scene(self, overrides: Optional[Mapping[str, Any]] = None) -> Scene:
        """The :class:`Scene` of this model, read and validated by the scene reader with
        ``overrides`` (as ``Scene.load``'s) applied. A value it refuses raises
        :class:`SceneError` naming the builder call and argument that wrote it."""
        text, lines = self._render()
        try:
            return Scene.from_toml(text, overrides, path=self._path())
        except SceneError as error:
            raise self._located(error, lines) from None

    def __repr__(self) -> str:
        arrays = self._arrays.items()
        counts = ", ".join(f"{len(items)} {table}" for table, items in arrays if items)
        return f"<Model {self.title!r}: {counts or 'empty'}>"

    # Building.

    def _path(self) -> str:
        return f"<Model {self.title!r}>"

    def _named(
        self, method: str, name: Optional[str], keys: Mapping[str, Any], shown: Sequence[str]
    ) -> "Model":
        """A shape, spring or loop: named by its name if it has one, else by ``shown``."""
        if name is None:
            return self._entry(_Call(method, keys, shown=shown))
        return self._entry(_Call(method, {"name": name, **keys}, lead="name"))

    def _table(self, table: str, keys: Mapping[str, Any]) -> "Model":
        section = _BY_TABLE[table]
        self._set(section, keys, _Call(section.method, keys))
        return self

    def _entry(self, call: _Call) -> "Model":
        """Adds a table to an array of tables, or changes the one its ``lead`` (its name,
        or a pair's shapes) names."""
        section = _BY_METHOD[call.method]
        values = self._checked(section, call.given, call)
        items = self._arrays[section.table]
        lead = call.lead
        same = [i for i in items if lead and lead in i.keys and i.keys[lead][0] == values[lead]]
        item = same[0] if same else None
        if item is None:
            item = _Item(call)
            items.append(item)
        self._write(item, values, call)
        return self

    def _set(
        self, section: _Section, keys: Mapping[str, Any], call: _Call, free: bool = False
    ) -> None:
        values = self._checked(section, keys, call, free)
        if section.table == "meta" and "title" in values and values["title"] is None:
            raise TypeError(f"{call.text('title')}: title: expected a string (a model has one)")
        item = self._tables.setdefault(section.table, _Item(call))
        self._write(item, values, call)

    @staticmethod
    def _write(item: _Item, values: Mapping[str, Any], call: _Call) -> None:
        for key, value in values.items():
            if value is None:
                item.keys.pop(key, None)
            else:
                item.keys[key] = (value, call)

    @staticmethod
    def _checked(
        section: _Section, keys: Mapping[str, Any], call: _Call, free: bool = False
    ) -> Dict[str, Any]:
        """The keys as plain Python values; ``TypeError`` naming the call for an unknown
        keyword or a value of the wrong type (``free``: any key, as ``[meta]``'s)."""
        values: Dict[str, Any] = {}
        for key, value in keys.items():
            # A key that is a Python keyword (a capsule's `from`) is written `from_`.
            if key.endswith("_") and keyword.iskeyword(key[:-1]):
                key = key[:-1]
            known = section.keys.get(key)
            if known is None and not free:
                raise TypeError(f"{call.text()}: {_unknown(section, key)}")
            kind = known[0] if known else VALUE
            if value is None:
                values[key] = None
                continue
            plain = _plain(value, kind)
            if plain is None:
                raise TypeError(
                    f"{call.text(key)}: {key}: expected {kind}, "
                    f"got {type(value).__name__} {_shown(value)}"
                )
            problem = _unwritable(plain)
            if problem is not None:
                raise _scene_error(f"{call.text(key)}: {key}: {problem}", call, key, None)
            values[key] = plain
        return values

    # Writing and reading back.

    def _render(self) -> Tuple[str, List[Tuple[_Call, Optional[str]]]]:
        """The scene text and, per line, the call (and key) that wrote it."""
        lines: List[Tuple[str, Tuple[_Call, Optional[str]]]] = []
        for section in _SECTIONS:
            items = self._arrays[section.table] if section.many else (
                [self._tables[section.table]] if section.table in self._tables else []
            )
            for item in items:
                if lines:
                    lines.append(("", (item.call, None)))
                header = f"[[{section.table}]]" if section.many else f"[{section.table}]"
                lines.append((header, (item.call, None)))
                order = list(section.keys) + [k for k in item.keys if k not in section.keys]
                for key in order:
                    if key in item.keys:
                        value, call = item.keys[key]
                        lines.append((f"{_toml_key(key)} = {_toml(value)}", (call, key)))
        text = "".join(line + "\n" for line, _ in lines)
        return text, [at for _, at in lines]

    def _located(
        self, error: SceneError, lines: List[Tuple[_Call, Optional[str]]]
    ) -> SceneError:
        """``error`` of the scene reader restated at the builder call that wrote the value;
        an error of an override is returned as it is."""
        if getattr(error, "override", None) is not None:
            return error
        key = getattr(error, "key", None)
        message = getattr(error, "message", None) or str(error)
        found = self._by_key(key) if key else None
        if found is None and getattr(error, "line", None):
            call, argument = lines[min(error.line, len(lines)) - 1]
            found = (call, argument, argument or key or "")
        if found is None:
            model = _Call("", {"title": self.title}, lead="title")
            text = f"{model.text()}: {key + ': ' if key else ''}{message}"
            located = _scene_error(text, model, None, key)
        else:
            call, argument, relative = found
            where = f"{relative}: " if relative else ""
            text = f"{call.text(argument)}: {where}{message}"
            located = _scene_error(text, call, argument, key)
        for name in ("file", "line", "column", "override"):
            setattr(located, name, getattr(error, name, None))
        located.message = message
        return located

    def _by_key(self, key: str) -> Optional[Tuple[_Call, Optional[str], str]]:
        """The call and argument behind the dotted key ``key`` (``bodies[1].mass``), and
        the key relative to that call's table (``mass``); None if no call wrote its table."""
        m = _KEY_PATH.match(key)
        if m is None or m["table"] not in _BY_TABLE:
            return None
        table, index, arg, rest = m["table"], m["index"], m["key"], m["rest"]
        if _BY_TABLE[table].many:
            items = self._arrays[table]
            if index is None or int(index) >= len(items):
                return None
            item = items[int(index)]
        elif table in self._tables:
            item = self._tables[table]
        else:
            return None
        relative = (arg or "") + rest
        if arg is not None and arg in item.keys:
            return item.keys[arg][1], arg, relative
        return item.call, None, relative

    @classmethod
    def _from_document(cls, document: Mapping[str, Any], title: str) -> "Model":
        """The model of a scene's document (``Scene.model``): one call per table."""
        meta = dict(document.get("meta", {}))
        meta.pop("title", None)
        model = cls(title, **meta)
        for section in _SECTIONS:
            if section.table == "meta" or section.table not in document:
                continue
            method = getattr(model, section.method)
            for table in document[section.table] if section.many else [document[section.table]]:
                method(**table)
        return model


def _unwritable(value: Any) -> Optional[str]:
    """Why the plain value ``value`` cannot be written in a scene file, if it cannot: an
    integer beyond TOML's 64 bits, or text that is not Unicode (a lone surrogate)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > _MAX_INT:
        return f"the integer {value} does not fit in 64 bits"
    if isinstance(value, str):
        try:
            value.encode("utf-8")
        except UnicodeEncodeError as error:
            return f"the text {_shown(value)} is not Unicode ({error.reason})"
        return None
    if isinstance(value, dict):
        children = [*value.keys(), *value.values()]
    else:
        children = value if isinstance(value, list) else []
    for child in children:
        problem = _unwritable(child)
        if problem is not None:
            return problem
    return None


def _unknown(section: _Section, key: str) -> str:
    """Why ``key`` is not a keyword of ``section``'s method: a likely misspelling, or the
    methods whose tables have it."""
    close = difflib.get_close_matches(key, section.keys, n=1, cutoff=0.75)
    if close:
        return f"unknown keyword '{key}'; did you mean '{close[0]}'?"
    elsewhere = [f"Model.{s.method}" for s in _SECTIONS if key in s.keys and s is not section]
    hint = f" (a key of {', '.join(elsewhere)})" if elsewhere else ""
    keys = ", ".join(section.keys)
    return f"unknown keyword '{key}'{hint}; the keys of [{section.table}] are {keys}"


def _scene_error(
    text: str, call: _Call, argument: Optional[str], key: Optional[str]
) -> SceneError:
    error = SceneError(text)
    error.call, error.argument, error.key = call.text(argument), argument, key
    error.file = error.line = error.column = error.override = None
    error.message = text
    return error


def _document_methods() -> None:
    """Writes each builder method's docstring from its table's keys."""
    intro = {
        "meta": "``[meta]``: ``title``, ``source``, ``notes`` and any other key (free-form).",
        "simulation": "``[simulation]``: how to simulate.",
        "summary": "``[summary]``: the run summary's windows.",
        "environment": "``[environment]``: the terrain and the default contact material.",
        "body_contacts": "``[body_contacts]``: contacts between shapes of different bodies.",
        "controller": "``[controller]``: the controller and its parameters.",
        "initial": "``[initial]``: the initial state.",
        "body": "A body (``[[bodies]]``), parents first; the same name again changes it.",
        "shape": "A contact shape (``[[shapes]]``); the same name again changes it.",
        "spring": "A linear spring between points of two bodies (``[[springs]]``).",
        "contact_pair": "An explicit body–body contact pair (``[[contact_pairs]]``).",
        "loop": "A loop joint closing a kinematic loop (``[[loops]]``); the same name again "
        "changes it.",
        "actuator": "A motor or servo in a body's joint (``[[actuators]]``).",
    }
    for section in _SECTIONS:
        method = getattr(Model, section.method)
        method.__doc__ = f"{intro[section.method]} Keys (SI units):\n\n{section.doc()}\n"


_document_methods()
