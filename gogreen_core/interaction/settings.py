"""The settings model: one evented source of truth for what an artist tunes (no Qt).

In napari's style: a model holds plain values in declared :class:`Field` s; setting a field
validates it (ParameterError naming it) and, when the value changes, emits
``model.events.<field>`` (a :class:`ChangeEvent`), then ``model.events.changed`` (:class:`Changes`)
once per update. Views bind to it both ways; :class:`EngineLink` feeds the engine from it::

    settings = Settings()
    settings.brush.events.radius.connect(lambda e: print("radius", e.value))
    settings.brush.radius = 0.05                     # validated, emitted
    link = EngineLink(settings, sculptor)            # material/falloff/pins reach the engine
    settings.material = Material.isotropic(1, 0.45)  # -> sculptor.apply_settings(...)

The fields are rows of the setting table (:mod:`gogreen_core.sculpt.setting_table`),
:data:`PEN_ROWS` and :data:`VIEW_ROWS`; values are immutable (a change is an assignment).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from gogreen_core.field.limits import check_falloff
from gogreen_core.files.presets import Preset
from gogreen_core.physics.radial import GaussianRadial, SplineRadial
from gogreen_core.sculpt.brushes import AUTO_INFLUENCE, DEFAULT_BRUSH, Brush
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.engine_settings import (
    SETTING_GROUPS,
    EngineSettings,
    resized_brush_weights,
)
from gogreen_core.sculpt.setting_table import Setting, rows
from gogreen_core.validation import ParameterError, check_type

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = [
    "ENGINE_FIELDS",
    "MATCAPS",
    "PEN_ROWS",
    "SHADINGS",
    "VIEW_ROWS",
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
    """A declared model field: ``default`` (a value, or a callable making one) and ``validate``
    ``(model, name, value) -> value`` (raising :class:`ParameterError`; None accepts anything).
    Values are compared with ``==`` (arrays with ``np.array_equal``)."""

    def __init__(
        self, default: Any, validate: Callable[[Any, str, Any], Any] | None = None, doc: str = ""
    ) -> None:
        self.default, self.validate, self.__doc__ = default, validate, doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, model: EventedModel | None, owner: type) -> Any:
        if model is None:
            return self
        return model._values[self.name]

    def __set__(self, model: EventedModel, value: Any) -> None:
        model.set(self.name, value)

    @staticmethod
    def equal(a: Any, b: Any) -> bool:
        if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            return a is not None and b is not None and np.array_equal(a, b)
        return bool(a == b)


class EventedModel:
    """Base of the evented models: declared :class:`Field` s, validated, with change events."""

    fields: ClassVar[dict[str, Field]] = {}

    def __init_subclass__(cls, made: Mapping[str, Field] | None = None, **kwargs: Any) -> None:
        """``made``: fields made elsewhere (from the setting table), before the class's own."""
        super().__init_subclass__(**kwargs)
        for name, made_field in (made or {}).items():
            made_field.__set_name__(cls, name)
            setattr(cls, name, made_field)
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
        """Set one field (see :meth:`update`; a drag's later steps are ``continued``)."""
        self.update({name: value}, continued=continued, source=source)

    def update(
        self, values: dict[str, Any], *, continued: bool = False, source: str = ""
    ) -> frozenset[str]:
        """Validate all ``values`` first (nothing changes if one is bad), then store them and
        emit one event per changed field and one ``changed``. Returns the changed names."""
        unknown = sorted(set(values) - set(self.fields))
        if unknown:
            raise ParameterError(unknown[0], f"{type(self).__name__} has no setting {unknown[0]!r}")
        new = self._normalize(dict(values))
        changed = [n for n in self.fields if n in new and not Field.equal(self._values[n], new[n])]
        old = {n: self._values[n] for n in changed}
        self._values.update({n: new[n] for n in changed})
        for name in changed:
            self.events[name].emit(ChangeEvent(name, new[name], old[name], continued, source))
        if changed:
            self.events.changed.emit(Changes(frozenset(changed), continued, source))
        return frozenset(changed)

    def _normalize(self, values: dict[str, Any]) -> dict[str, Any]:
        """Validated ``values`` (field order); a subclass may check dependent fields here."""
        out = {}
        for name, f in self.fields.items():
            if name in values:
                out[name] = f.validate(self, name, values[name]) if f.validate else values[name]
        return out

    def values(self) -> dict[str, Any]:
        """The current values by field name (a shallow copy)."""
        return dict(self._values)


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
    influence = Field(AUTO_INFLUENCE, _brush_value, doc='moved region in ε, or "auto"')
    symmetry = Field("", _brush_value, doc='mirror planes, any of "x", "y", "z"')

    @property
    def brush(self) -> Brush:
        return Brush(**self._values)

    def set_brush(self, brush: Brush, *, continued: bool = False) -> None:
        self.update(asdict(check_type("brush", brush, Brush)), continued=continued)


def _row_fields(table: Iterable[Setting], prefix: str = "") -> dict[str, Field]:
    """One field per row, checked by the row (named ``prefix`` + the field's name); falloff and
    weights rows are checked with l_max in :meth:`Settings._normalize`."""

    def field(row: Setting) -> Field:
        if row.type in ("falloff", "weights"):
            return Field(None, doc=row.doc)
        return Field(
            row.default, lambda _model, name, value: row.check(value, prefix + name), doc=row.doc
        )

    return {row.name: field(row) for row in table}


class _Rows(EventedModel):
    if TYPE_CHECKING:  # the fields are made from rows (values of any type)

        def __getattr__(self, name: str) -> Any: ...
        def __setattr__(self, name: str, value: Any) -> None: ...


#: How a pen (or the mouse) drives a stroke, as in Blender (read by
#: :class:`gogreen_core.interaction.tools.StrokeController`).
PEN_ROWS = (
    Setting("pressure_strength", "bool", True, "pen pressure scales each event's step"),
    Setting("pressure_radius", "bool", False, "pen pressure scales ε (down to 0.1 ε)"),
    Setting("lazy_radius", "float", 0.0, "stabilizer: lag in screen pixels", low=0, high=1e3),
    Setting("spacing", "float", 0.0, "minimum motion between events, in ε", low=0, high=10),
)


class PenSettings(_Rows, made=_row_fields(PEN_ROWS, "pen.")):
    """The pen's settings (:data:`PEN_ROWS`; not part of presets or sessions)."""


#: How the viewport shades the model: a matcap (a lit sphere looked up by the view-space normal,
#: as in Blender and ZBrush) or studio lights; the matcaps (their pictures: app.matcaps).
SHADINGS = ("matcap", "studio")
MATCAPS = ("clay", "red_wax", "glossy", "basic")
#: How the viewport shows the model and moves its camera (the View menu).
VIEW_ROWS = (
    Setting("shading", "choice", "matcap", "matcap or studio lights", choices=SHADINGS),
    Setting("matcap", "choice", "clay", "the matcap's picture", choices=MATCAPS),
    Setting("cavity", "bool", False, "tint the surface by its curvature (darker in hollows)"),
    Setting("falloff_profile", "bool", False, "the falloff profile over the brush ring always"),
    Setting("zoom_to_mouse", "bool", True, "the wheel zooms about the cursor, not the centre"),
)


class ViewSettings(_Rows, made=_row_fields(VIEW_ROWS, "view.")):
    """The viewport's settings (:data:`VIEW_ROWS`; the app keeps them between runs, not in
    presets or sessions, which describe the model)."""


def needed_curves(l_max: int) -> list[tuple[str, int]]:
    """Curves a kernel of ``l_max`` uses: R_l for even l ≤ l_max, ℛ_l for odd l ≤ l_max + 1,
    by degree."""
    keys = [("R", l) for l in range(0, l_max + 1, 2)] + [("dR", l) for l in range(1, l_max + 2, 2)]
    return sorted(keys, key=lambda k: (k[1], k[0]))


class Settings(_Rows, made=_row_fields(rows("app"))):
    """What the engine, presets and the app's panels share: one field per ``"app"`` row of the
    setting table, and the sub-models ``brush`` (:class:`BrushSettings`), ``pen`` and ``view``.
    The falloff is a :class:`SplineRadial` at ε = 1 with the curves :func:`needed_curves` of
    ``l_max`` (missing ones: Gaussian); a profile assigned replaces the curves it has."""

    def __init__(self, **values: Any) -> None:
        self.brush = BrushSettings()
        self.pen = PenSettings()
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
        missing = [key for key in needed_curves(l_max) if key not in set(spline.curve_keys())]
        if not missing:
            return spline
        gaussian = SplineRadial.from_profile(GaussianRadial(1.0), l_max)
        return spline.with_curves({key: gaussian.curve(*key) for key in missing})

    @property
    def engine_settings(self) -> EngineSettings:
        """The engine's settings as one value (rows the app does not show at their defaults)."""
        return EngineSettings(**{name: self._values[name] for name in ENGINE_FIELDS})

    def weights_for(self, kind: str) -> np.ndarray:
        """Brush ``kind``'s degree weights ω_l (l_max + 2,) (:meth:`EngineSettings.weights_for`)."""
        return self.engine_settings.weights_for(kind)

    def set_brush_weights(
        self, kind: str, weights: Sequence[float] | None, *, continued: bool = False
    ) -> None:
        """Give brush ``kind`` the degree weights ``weights`` (None: its defaults)."""
        value = self.engine_settings.with_brush_weights(kind, weights)
        self.update({"brush_weights": value.brush_weights}, continued=continued)

    def preset(self, name: str = "", description: str = "") -> Preset:
        """The current settings as a :class:`Preset` (values: later edits do not reach it)."""
        values = {s.name: self._values[s.name] for s in rows("preset")}
        return Preset(name, brush=self.brush.brush, description=description, **values)

    def apply_preset(self, preset: Preset) -> None:
        """Take every setting of ``preset`` (one update of this model, then the brush)."""
        self.update({s.name: getattr(preset.settings, s.name) for s in rows("preset")})
        self.brush.set_brush(preset.brush)

    def sculptor_options(self) -> dict[str, Any]:
        """Keyword arguments of :class:`gogreen_core.Sculptor` for a new mesh."""
        return {"settings": self.engine_settings}


#: The model's fields that are the engine's settings.
ENGINE_FIELDS = tuple(s.name for s in rows("engine") if "app" in s.places)


class EngineLink:
    """Feeds a :class:`gogreen_core.Sculptor` from a :class:`Settings` (one
    ``apply_settings`` per update, with the updated fields' :data:`SETTING_GROUPS`) and pulls
    back (:meth:`pull`, after undo/redo). An engine that refuses is left as it was; the link
    restores the settings from it and calls ``on_error(parameter, exc)``."""

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
        names = [name for name in ENGINE_FIELDS if not engine.agrees(model, (name,))]
        values = {name: getattr(engine, name) for name in names}
        if values:
            self._pulling = True
            try:
                self.settings.update(values, source="engine")
            finally:
                self._pulling = False
