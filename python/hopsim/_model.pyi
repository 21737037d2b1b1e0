"""Type stubs of hopsim._model: the builder's keywords, one per key of the scene format
(docs/scene-format.md, SI units; see the docstrings at run time). ``None`` removes a key."""

from typing import Any, Mapping, Optional, Sequence

from ._hopsim import Scene

_Vec2 = Sequence[float]

class Model:
    def __init__(self, title: str = "model", **meta: Any) -> None: ...
    @property
    def title(self) -> str: ...
    def toml(self) -> str: ...
    def scene(self, overrides: Optional[Mapping[str, Any]] = None) -> Scene: ...
    def meta(
        self, *, title: str = ..., source: Optional[str] = ..., notes: Optional[str] = ..., **free: Any
    ) -> "Model": ...
    def simulation(
        self,
        *,
        duration: Optional[float] = ...,
        dt: Optional[float] = ...,
        gravity: Optional[float] = ...,
        gravity_x: Optional[float] = ...,
        record_rate: Optional[float] = ...,
        strict: Optional[bool] = ...,
        warm_start: Optional[bool] = ...,
        max_speed: Optional[float] = ...,
        max_steps: Optional[float] = ...,
    ) -> "Model": ...
    def summary(
        self,
        *,
        speed_window: Optional[float] = ...,
        cube_restitution: Optional[float] = ...,
    ) -> "Model": ...
    def environment(
        self,
        *,
        terrain: Optional[str] = ...,
        height: Optional[float] = ...,
        angle: Optional[float] = ...,
        step_x: Optional[float] = ...,
        step_height: Optional[float] = ...,
        friction: Optional[float] = ...,
        restitution: Optional[float] = ...,
        tangential_restitution: Optional[float] = ...,
    ) -> "Model": ...
    def body(
        self,
        name: str,
        *,
        mass: Optional[float] = ...,
        inertia: Optional[float] = ...,
        parent: Optional[str] = ...,
        base: Optional[str] = ...,
        joint: Optional[str] = ...,
        axis: Optional[_Vec2] = ...,
        pivot: Optional[_Vec2] = ...,
        com: Optional[_Vec2] = ...,
        coordinate: Optional[str] = ...,
        coordinate_name: Optional[str] = ...,
        damping: Optional[float] = ...,
        armature: Optional[float] = ...,
        dry_friction: Optional[float] = ...,
        stiffness: Optional[float] = ...,
        rest_position: Optional[float] = ...,
        limits: Optional[_Vec2] = ...,
        limit_restitution: Optional[float] = ...,
        position: Optional[_Vec2] = ...,
        angle: Optional[float] = ...,
    ) -> "Model": ...
    def shape(
        self,
        name: Optional[str] = None,
        *,
        body: Optional[str] = ...,
        type: Optional[str] = ...,
        friction: Optional[float] = ...,
        restitution: Optional[float] = ...,
        tangential_restitution: Optional[float] = ...,
        switchable: Optional[bool] = ...,
        group: Optional[float] = ...,
        collides_with: Optional[Sequence[float]] = ...,
        center: Optional[_Vec2] = ...,
        radius: Optional[float] = ...,
        start: Optional[float] = ...,
        end: Optional[float] = ...,
        semi_x: Optional[float] = ...,
        semi_y: Optional[float] = ...,
        position: Optional[_Vec2] = ...,
        vertices: Optional[Sequence[_Vec2]] = ...,
        half_width: Optional[float] = ...,
        half_height: Optional[float] = ...,
        from_: Optional[_Vec2] = ...,
        to: Optional[_Vec2] = ...,
    ) -> "Model": ...
    def spring(
        self,
        name: Optional[str] = None,
        *,
        body_a: Optional[str] = ...,
        body_b: Optional[str] = ...,
        point_a: Optional[_Vec2] = ...,
        point_b: Optional[_Vec2] = ...,
        stiffness: Optional[float] = ...,
        rest_length: Optional[float] = ...,
        damping: Optional[float] = ...,
        tension_only: Optional[bool] = ...,
    ) -> "Model": ...
    def body_contacts(
        self,
        *,
        all: Optional[bool] = ...,
        friction: Optional[float] = ...,
        restitution: Optional[float] = ...,
        tangential_restitution: Optional[float] = ...,
    ) -> "Model": ...
    def contact_pair(
        self,
        shapes: Sequence[str],
        *,
        friction: Optional[float] = ...,
        restitution: Optional[float] = ...,
        tangential_restitution: Optional[float] = ...,
    ) -> "Model": ...
    def loop(
        self,
        name: Optional[str] = None,
        *,
        type: Optional[str] = ...,
        body_a: Optional[str] = ...,
        point_a: Optional[_Vec2] = ...,
        body_b: Optional[str] = ...,
        point_b: Optional[_Vec2] = ...,
        length: Optional[float] = ...,
        angle: Optional[float] = ...,
        axis: Optional[_Vec2] = ...,
    ) -> "Model": ...
    def actuator(
        self,
        name: Optional[str] = None,
        *,
        joint: Optional[str] = ...,
        kind: Optional[str] = ...,
        gear: Optional[float] = ...,
        kp: Optional[float] = ...,
        kv: Optional[float] = ...,
        ctrl_range: Optional[_Vec2] = ...,
        force_range: Optional[_Vec2] = ...,
        control: Optional[Mapping[str, Any]] = ...,
    ) -> "Model": ...
    def controller(
        self,
        *,
        type: Optional[str] = ...,
        flywheel: Optional[str] = ...,
        torque: Optional[float] = ...,
        impulse_limit: Optional[float] = ...,
        release: Optional[str] = ...,
        rearm_timeout: Optional[float] = ...,
        off_time: Optional[float] = ...,
        hold_brake: Optional[bool] = ...,
        joint: Optional[str] = ...,
        force: Optional[float] = ...,
        pulse_duration: Optional[float] = ...,
        period: Optional[float] = ...,
        frequency: Optional[float] = ...,
        cane: Optional[str] = ...,
        cane_mode: Optional[str] = ...,
        cane_delay: Optional[float] = ...,
        cane_duration: Optional[float] = ...,
        cane_schedule: Optional[str] = ...,
    ) -> "Model": ...
    def initial(
        self,
        *,
        q: Optional[Sequence[float]] = ...,
        u: Optional[Sequence[float]] = ...,
        rest_on_ground: Optional[bool] = ...,
    ) -> "Model": ...
