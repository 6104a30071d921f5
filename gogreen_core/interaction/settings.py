"""The settings model: one evented source of truth for what an artist tunes (no Qt).

In napari's style: a model holds plain values in declared :class:`Field` s; setting a field
validates it (:class:`gogreen_core.validation.ParameterError` naming the field), and when the
value changes, emits ``model.events.<field>`` with a :class:`ChangeEvent`, then
``model.events.changed`` once per update with the set of changed names. Views (the app's
panels and brush bar) bind to it both ways; the engine is fed from it by :class:`EngineLink`;
presets are made from and applied to it::

    settings = Settings()
    settings.brush.events.radius.connect(lambda e: print("radius", e.value))
    settings.brush.radius = 0.05                     # validated, emitted
    link = EngineLink(settings, sculptor)            # material/falloff/pins reach the engine
    settings.material = Material.isotropic(1, 0.45)  # -> sculptor.apply_settings(...)

Every value is immutable (a new one per change; the falloff too, compared by content), so a
change is an assignment and an equal value is no change.

Adding a setting: declare one ``Field`` on the model (with its validator) and bind one widget
to it; a brush field also needs the same name on :class:`gogreen_core.sculpt.brushes.Brush` (which
already carries it into strokes, sessions and presets); an engine field also needs the same
name on :class:`gogreen_core.sculpt.engine_settings.EngineSettings` (which carries it to the
sculptor, sessions and undo).

Drags: a slider or curve drag sets its field once per step with ``continued=True`` after the
first step; :class:`EngineLink` forwards that flag to the engine in its one typed call
(:meth:`EngineLink.send`), so that a whole drag can be one undo step.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, fields, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from gogreen_core.field.limits import (
    check_constraint_radius,
    check_detail_size,
    check_falloff,
    check_l_max,
    check_material,
)
from gogreen_core.files.presets import Preset
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial, SplineRadial
from gogreen_core.sculpt.brushes import AUTO_INFLUENCE, DEFAULT_BRUSH, Brush
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.engine_settings import (
    DEFAULT_CONSTRAINT_RADIUS,
    MATERIAL_FRAMES,
    SETTING_GROUPS,
    EngineSettings,
    resized_brush_weights,
)
from gogreen_core.validation import ParameterError, check_bool, check_choice, check_number

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = [
    "ENGINE_FIELDS",
    "MATCAPS",
    "SHADINGS",
    "BrushSettings",
    "ChangeEvent",
    "EngineLink",
    "EventEmitter",
    "EventedModel",
    "Field",
    "PenSettings",
    "Settings",
    "ViewSettings",
    "needed_curves",
]


@dataclass(frozen=True)
class ChangeEvent:
    """A field change: ``name``, new ``value``, ``old`` value, ``continued`` (a further step of
    a drag), ``source`` (who made it, e.g. ``"engine"`` when pulled back from the engine)."""

    name: str
    value: Any
    old: Any
    continued: bool = False
    source: str = ""


@dataclass(frozen=True)
class Changes:
    """One update: the changed field ``names``, ``continued``, ``source``."""

    names: frozenset[str]
    continued: bool = False
    source: str = ""


class EventEmitter:
    """A list of callbacks called with one event (synchronously, in connection order)."""

    def __init__(self) -> None:
        self._callbacks: list[Callable[[Any], None]] = []

    def connect(self, callback: Callable[[Any], None]) -> Callable[[Any], None]:
        self._callbacks.append(callback)
        return callback

    def disconnect(self, callback: Callable[[Any], None]) -> None:
        if callback in self._callbacks:
            self._callbacks.remove(callback)

    def emit(self, event: Any) -> None:
        for callback in list(self._callbacks):
            callback(event)

    def __len__(self) -> int:
        return len(self._callbacks)


class _Events:
    """``events.<field>`` emitters plus ``events.changed``."""

    def __init__(self, names: Iterable[str]) -> None:
        self.changed = EventEmitter()
        self._emitters = {name: EventEmitter() for name in names}

    def __getattr__(self, name: str) -> EventEmitter:
        try:
            return self._emitters[name]
        except KeyError:
            raise AttributeError(f"no event {name!r}") from None

    def __getitem__(self, name: str) -> EventEmitter:
        return self._emitters[name]


class Field:
    """A declared model field.

    default : the value, or a zero-argument callable making it (mutable defaults).
    validate : ``(model, name, value) -> value`` normalizing a value or raising
        :class:`ParameterError`; None accepts anything.
    eq : ``(a, b) -> bool``, when a new value equals the old (no event); default ``==`` (arrays
        compared with ``np.array_equal``).
    """

    def __init__(
        self,
        default: Any,
        validate: Callable[[Any, str, Any], Any] | None = None,
        eq: Callable[[Any, Any], bool] | None = None,
        doc: str = "",
    ) -> None:
        self.default, self.validate, self.eq, self.__doc__ = default, validate, eq, doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, model: EventedModel | None, owner: type) -> Any:
        if model is None:
            return self
        return model._values[self.name]

    def __set__(self, model: EventedModel, value: Any) -> None:
        model.set(self.name, value)

    def equal(self, a: Any, b: Any) -> bool:
        if self.eq is not None:
            return bool(self.eq(a, b))
        if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            return a is not None and b is not None and np.array_equal(a, b)
        return bool(a == b)


class EventedModel:
    """Base of the evented models: declared :class:`Field` s, validated, with change events.

    Subclasses may override :meth:`_normalize` to validate fields that depend on each other.
    """

    fields: ClassVar[dict[str, Field]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        fields: dict[str, Field] = {}
        for klass in reversed(cls.__mro__):
            fields.update({k: v for k, v in vars(klass).items() if isinstance(v, Field)})
        cls.fields = fields

    def __init__(self, **values: Any) -> None:
        self._values: dict[str, Any] = {}
        for name, f in self.fields.items():
            default = f.default() if callable(f.default) else f.default
            self._values[name] = f.validate(self, name, default) if f.validate else default
        self.events = _Events(self.fields)
        if values:
            self.update(values)

    def set(self, name: str, value: Any, *, continued: bool = False, source: str = "") -> None:
        """Set one field (see :meth:`update`)."""
        self.update({name: value}, continued=continued, source=source)

    def update(
        self, values: dict[str, Any], *, continued: bool = False, source: str = ""
    ) -> frozenset[str]:
        """Validate all ``values`` first (nothing changes if one is bad), then store them and
        emit one event per changed field and one ``changed``. Returns the changed names."""
        unknown = set(values) - set(self.fields)
        if unknown:
            name = sorted(unknown)[0]
            raise ParameterError(name, f"{type(self).__name__} has no setting {name!r}")
        new = self._normalize(dict(values))
        changed = [n for n in self.fields if n in new and not self._same(n, new[n])]
        old = {n: self._values[n] for n in changed}
        for name in changed:
            self._values[name] = new[name]
        for name in changed:
            self.events[name].emit(ChangeEvent(name, new[name], old[name], continued, source))
        if changed:
            self.events.changed.emit(Changes(frozenset(changed), continued, source))
        return frozenset(changed)

    def _same(self, name: str, value: Any) -> bool:
        return self.fields[name].equal(self._values[name], value)

    def _normalize(self, values: dict[str, Any]) -> dict[str, Any]:
        """Validated ``values`` (field order); may add dependent fields."""
        out = {}
        for name, f in self.fields.items():
            if name in values:
                out[name] = f.validate(self, name, values[name]) if f.validate else values[name]
        return out

    def values(self) -> dict[str, Any]:
        """The current values by field name (a shallow copy)."""
        return dict(self._values)


# -- brush -----------------------------------------------------------------------------------
def _brush_value(model: BrushSettings, name: str, value: Any) -> Any:
    """Validated by :class:`Brush` itself, so the model and the engine accept the same."""
    base = Brush(**model._values) if len(model._values) == len(model.fields) else Brush()
    try:
        return getattr(replace(base, **{name: value}), name)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"brush.{name}", str(exc)) from None


class BrushSettings(EventedModel):
    """The brush of the next stroke; :attr:`brush` is it as an immutable :class:`Brush`."""

    kind = Field(DEFAULT_BRUSH, _brush_value, doc="one of BRUSH_KINDS (key 1's at first)")
    radius = Field(0.08, _brush_value, doc="ε as a fraction of the model size")
    strength = Field(1.0, _brush_value, doc="multiplies the cursor motion or amount")
    substeps = Field(0, _brush_value, doc="RK4 steps per mouse event (0: adaptive)")
    influence = Field(
        AUTO_INFLUENCE,
        _brush_value,
        doc='radius of the moved region, in multiples of ε, or "auto" (where the field fades)',
    )
    symmetry = Field("", _brush_value, doc='mirror planes, any of "x", "y", "z"')

    @property
    def brush(self) -> Brush:
        return Brush(**self._values)

    def set_brush(self, brush: Brush, *, continued: bool = False) -> None:
        if not isinstance(brush, Brush):
            raise ParameterError("brush", f"brush must be a Brush (got {type(brush).__name__})")
        self.update(asdict(brush), continued=continued)


# -- pen ---------------------------------------------------------------------------------------
def _flag(_model: PenSettings, name: str, value: Any) -> bool:
    return check_bool(f"pen.{name}", value)


def _pen_number(high: float) -> Callable[[PenSettings, str, Any], float]:
    def validate(_model: PenSettings, name: str, value: Any) -> float:
        return check_number(f"pen.{name}", value, low=0.0, high=high)

    return validate


class PenSettings(EventedModel):
    """How a pen (or the mouse) drives a stroke, as in Blender: pressure toggles for the
    strength and the radius, a stabilizer and event spacing (the stroke controller reads them,
    :class:`gogreen_core.interaction.tools.StrokeController`).

    pressure_strength : pressure scales each event's step (the strength).
    pressure_radius : pressure scales each event's radius ε along the stroke (Blender's habit):
        the event's :attr:`BrushEvent.radius_factor` is the pressure, at least
        :data:`gogreen_core.interaction.tools.MIN_PRESSURE_RADIUS`.
    lazy_radius : stabilizer, screen pixels: the brush follows the pointer at this distance
        behind it (a rope of that length), smoothing jitter; 0: off.
    spacing : a move is applied only once the brush point has gone this many ε from the last
        applied one; 0: every move.
    """

    pressure_strength = Field(True, _flag, doc="pen pressure scales each event's step")
    pressure_radius = Field(False, _flag, doc="pen pressure scales the radius along the stroke")
    lazy_radius = Field(0.0, _pen_number(1000.0), doc="stabilizer: lag in screen pixels")
    spacing = Field(0.0, _pen_number(10.0), doc="minimum motion between events, in ε")


# -- view --------------------------------------------------------------------------------------
#: How the viewport shades the model: a matcap (a lit sphere looked up by the view-space normal,
#: as in Blender and ZBrush) or studio lights; the matcaps (their pictures: app.matcaps).
SHADINGS = ("matcap", "studio")
MATCAPS = ("clay", "red_wax", "glossy", "basic")


def _view_choice(choices: tuple[str, ...]) -> Callable[[ViewSettings, str, Any], str]:
    def validate(_model: ViewSettings, name: str, value: Any) -> str:
        return check_choice(f"view.{name}", value, choices)

    return validate


def _view_flag(_model: ViewSettings, name: str, value: Any) -> bool:
    return check_bool(f"view.{name}", value)


class ViewSettings(EventedModel):
    """How the viewport shows the model and moves its camera (the View menu; the app keeps
    them between runs; not part of presets or sessions, which describe the model):
    shading : one of :data:`SHADINGS`.
    matcap : one of :data:`MATCAPS`, the picture of the "matcap" shading.
    cavity : tint the surface by its curvature (darker in hollows, lighter on ridges), so that
        small changes of shape show.
    falloff_profile : draw the brush's falloff profile over its ring at all times (else only
        while F drags the radius).
    zoom_to_mouse : the wheel zooms towards the point under the cursor (Blender's "Zoom to
        Mouse Position"); off: towards the view's centre.
    """

    shading = Field("matcap", _view_choice(SHADINGS), doc="matcap or studio lights")
    matcap = Field("clay", _view_choice(MATCAPS), doc="the matcap's picture")
    cavity = Field(False, _view_flag, doc="curvature tint")
    falloff_profile = Field(False, _view_flag, doc="the falloff profile over the brush ring")
    zoom_to_mouse = Field(True, _view_flag, doc="the wheel zooms about the cursor")


# -- material, falloff, constraints ----------------------------------------------------------
def needed_curves(l_max: int) -> list[tuple[str, int]]:
    """Curves a kernel of ``l_max`` uses: R_l for even l ≤ l_max, ℛ_l for odd l ≤ l_max + 1,
    by degree."""
    keys = [("R", l) for l in range(0, l_max + 1, 2)] + [("dR", l) for l in range(1, l_max + 2, 2)]
    return sorted(keys, key=lambda k: (k[1], k[0]))


def _with_needed_curves(spline: SplineRadial, l_max: int) -> SplineRadial:
    """``spline`` with the curves of ``l_max`` it lacks taken from the Gaussian falloff (itself
    when it has them all)."""
    have = set(spline.curve_keys())
    missing = [key for key in needed_curves(l_max) if key not in have]
    if not missing:
        return spline
    gaussian = SplineRadial.from_profile(GaussianRadial(1.0), l_max)
    return spline.with_curves({key: gaussian.curve(*key) for key in missing})


# Each field is checked by the engine's own checks (gogreen_core.field.limits), named as the field.
def _material(_model: Settings, name: str, value: Any) -> Material:
    return check_material(value, name)


def _l_max(_model: Settings, name: str, value: Any) -> int:
    return check_l_max(value, name)


def _radius(_model: Settings, name: str, value: Any) -> float:
    return check_constraint_radius(value, name)


def _detail_size(_model: Settings, name: str, value: Any) -> float | None:
    return check_detail_size(value, name)


def _switch(_model: Settings, name: str, value: Any) -> bool:
    return check_bool(name, value)


def _frame(_model: Settings, name: str, value: Any) -> str:
    return check_choice(name, value, MATERIAL_FRAMES)


class Settings(EventedModel):
    """Brush, material, falloff and constraint settings: what the engine, presets and the
    app's panels share.

    Fields
    ------
    material : :class:`Material`
    l_max : int, SH truncation degree (0 … ``L_MAX_LIMIT``)
    falloff : :class:`SplineRadial`, an immutable value at ε = 1 (compared by content): assigning
        any single radial profile gives a spline with its curves (sampled when not a spline)
        replacing the current ones; an edit (the curve editor's) assigns a new value. It always
        has the curves :func:`needed_curves` of ``l_max`` (missing ones: Gaussian); curves above
        l_max are kept.
    constraint_radius : ε of the pins, as a fraction of the model size.
    brush_weights : per-brush degree weights ω_l (kind → l_max + 2 numbers, read-only mapping);
        changing l_max keeps the common degrees and gives new ones each brush's defaults.
    dynamic_topology : bool, strokes remesh what they move; detail_size : its target edge
        length as a fraction of the model size, or None (the edge length the surface had).
    material_frame : "world" or "surface" (the material's axes follow the surface where each
        stroke starts).

    :attr:`engine_settings` is the engine's part as one :class:`EngineSettings` value.
    ``brush`` is a :class:`BrushSettings` (a sub-model with events of its own), ``pen`` a
    :class:`PenSettings`, ``view`` a :class:`ViewSettings`.
    """

    material = Field(lambda: Material.isotropic(1.0, 0.3), _material)
    l_max = Field(8, _l_max)
    falloff = Field(None)  # checked in _normalize, with l_max
    constraint_radius = Field(DEFAULT_CONSTRAINT_RADIUS, _radius)
    brush_weights = Field(None)  # checked in _normalize, with l_max
    dynamic_topology = Field(False, _switch, doc="strokes remesh what they move")
    detail_size = Field(None, _detail_size, doc="target edge length / model size, or None")
    material_frame = Field("world", _frame, doc="world or surface: where the material's axes are")

    def __init__(self, **values: Any) -> None:
        self.brush = BrushSettings()
        #: Pen pressure, stabilizer and spacing (not part of presets or sessions).
        self.pen = PenSettings()
        #: Shading, cavity tint, overlay and zoom choices of the viewport (neither).
        self.view = ViewSettings()
        super().__init__()
        self._values.update(self._normalize({}))  # the spline and weights of the default l_max
        if values:
            self.update(values)

    def _normalize(self, values: dict[str, Any]) -> dict[str, Any]:
        out = super()._normalize(values)
        l_max = out.get("l_max", self._values.get("l_max", 8))
        first = self._values.get("falloff") is None  # construction
        if "falloff" in out or "l_max" in out or first:
            out["falloff"] = self._spline(out.get("falloff"), l_max)
        if "brush_weights" in out or "l_max" in out or first:
            given = out.get("brush_weights")
            if given is None:
                given = resized_brush_weights(self._values.get("brush_weights") or {}, l_max)
            out["brush_weights"] = check_brush_weights(given, l_max, "brush_weights")
        return out

    def _spline(self, profile: object, l_max: int) -> SplineRadial:
        current: SplineRadial | None = self._values.get("falloff")
        if profile is None:
            spline = current or SplineRadial.from_profile(GaussianRadial(1.0), l_max).as_value()
        else:
            shape = check_falloff(profile, "falloff")
            if not isinstance(shape, SplineRadial):
                shape = SplineRadial.from_profile(shape, l_max).as_value()
            spline = shape if current is None else current.with_curves(shape)
        return _with_needed_curves(spline, l_max)

    @property
    def engine_settings(self) -> EngineSettings:
        """Material, falloff, l_max, weights and the pins' radius as one engine value."""
        return EngineSettings(
            material=self.material,
            falloff=self.falloff,
            l_max=self.l_max,
            constraint_radius=self.constraint_radius,
            brush_weights=self.brush_weights,
            dynamic_topology=self.dynamic_topology,
            detail_size=self.detail_size,
            material_frame=self.material_frame,
        )

    def weights_for(self, kind: str) -> np.ndarray:
        """Brush ``kind``'s degree weights ω_l (l_max + 2,) (its defaults when it has none of its
        own)."""
        return self.engine_settings.weights_for(kind)

    def set_brush_weights(
        self, kind: str, weights: Sequence[float] | None, *, continued: bool = False
    ) -> None:
        """Give brush ``kind`` the degree weights ``weights`` (None: its defaults)."""
        value = self.engine_settings.with_brush_weights(kind, weights)
        self.update({"brush_weights": value.brush_weights}, continued=continued)

    # -- presets and the engine's options ----------------------------------------------------
    def preset(self, name: str = "", description: str = "") -> Preset:
        """The current settings as a :class:`Preset` (values: later edits do not reach it)."""
        return Preset(
            name=name,
            material=self.material,
            falloff=self.falloff,
            l_max=self.l_max,
            brush=self.brush.brush,
            description=description,
            brush_weights=self.brush_weights,
            material_frame=self.material_frame,
        )

    def apply_preset(self, preset: Preset) -> None:
        """Take every setting of ``preset`` (one update of this model, then the brush)."""
        self.update(
            {
                "material": preset.material,
                "l_max": preset.l_max,
                "falloff": preset.falloff,
                "brush_weights": preset.brush_weights,
                "material_frame": preset.material_frame,
            }
        )
        self.brush.set_brush(preset.brush)

    def sculptor_options(self) -> dict[str, Any]:
        """Keyword arguments of :class:`gogreen_core.Sculptor` for a new mesh: these
        :attr:`engine_settings`."""
        return {"settings": self.engine_settings}


#: The model's fields that are the engine's settings.
ENGINE_FIELDS = tuple(f.name for f in fields(EngineSettings))


class EngineLink:
    """Feeds a :class:`gogreen_core.Sculptor` from a :class:`Settings` and pulls back.

    Every update of the engine's fields reaches the engine as one typed call,
    ``sculptor.apply_settings(value, continued=...)``: ``value`` is the engine's settings with
    the updated fields' groups (:data:`SETTING_GROUPS`) taken from the model, one undo step per
    group, joined to the step before while a drag is ``continued``. An
    engine that refuses (``ValueError``, ``RuntimeError``) is left as it was; the link then
    restores the settings from the engine and calls ``on_error(parameter, exc)``, so model and
    engine never disagree. :meth:`pull` copies the engine's values into the settings (after
    undo/redo) without sending them back.
    """

    def __init__(
        self,
        settings: Settings,
        sculptor: Sculptor | None = None,
        on_error: Callable[[str, Exception], None] | None = None,
    ) -> None:
        self.settings = settings
        self.sculptor = sculptor
        self.on_error = on_error
        self._pulling = False
        settings.events.changed.connect(self._changed)

    def attach(self, sculptor: Sculptor | None) -> None:
        """Feed ``sculptor`` from now on (made with :meth:`Settings.sculptor_options`); gives
        it the settings it was not made with."""
        self.sculptor = sculptor
        if sculptor is not None:
            self.send(False, ENGINE_FIELDS)

    def _changed(self, changes: Changes) -> None:
        if self._pulling or self.sculptor is None or changes.source == "engine":
            return
        names = [name for name in ENGINE_FIELDS if name in changes.names]
        if names:
            self.send(changes.continued, names)

    def send(self, continued: bool, names: Sequence[str]) -> bool:
        """The one place settings reach the engine. False, after restoring the settings from
        the engine and reporting (the parameter, else the first of ``names``), when the engine
        refuses."""
        assert self.sculptor is not None
        model = self.settings.engine_settings
        groups = [group for group in SETTING_GROUPS if set(group) & set(names)]
        try:
            value = self.sculptor.settings.replace(
                **{name: getattr(model, name) for group in groups for name in group}
            )
            self.sculptor.apply_settings(value, continued=continued)
        except (ValueError, RuntimeError) as exc:
            self.pull()
            if self.on_error is None:
                raise
            self.on_error(getattr(exc, "parameter", None) or names[0], exc)
            return False
        return True

    def pull(self) -> None:
        """Copy the engine's settings into the model (no echo back to the engine)."""
        if self.sculptor is None:
            return
        engine, model = self.sculptor.settings, self.settings.engine_settings
        values = {
            name: getattr(engine, name)
            for name in ENGINE_FIELDS
            if not engine.agrees(model, (name,))
        }
        if values:
            self._pulling = True
            try:
                self.settings.update(values, source="engine")
            finally:
                self._pulling = False
