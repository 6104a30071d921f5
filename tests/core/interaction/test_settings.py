"""The evented settings model and its link to the engine: no window, no Qt."""

import numpy as np
import pytest

from gogreen_core.files.presets import Preset
from gogreen_core.interaction.settings import EngineLink, Settings, needed_curves
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, SplineRadial
from gogreen_core.sculpt.brushes import DEFAULT_BRUSH, Brush
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.validation import ParameterError


def record(emitter) -> list:
    events: list = []
    emitter.connect(events.append)
    return events


def test_a_field_change_emits_once_with_old_and_new_values():
    settings = Settings()
    radius = record(settings.brush.events.radius)
    changed = record(settings.brush.events.changed)
    settings.brush.radius = 0.05
    settings.brush.radius = 0.05  # same value: no event
    assert [(e.old, e.value) for e in radius] == [(0.08, 0.05)]
    assert [c.names for c in changed] == [frozenset({"radius"})]
    assert settings.brush.brush == Brush(DEFAULT_BRUSH, radius=0.05)


@pytest.mark.parametrize(
    ("name", "value", "parameter"),
    [
        ("radius", 0.0, "brush.radius"),
        ("strength", float("nan"), "brush.strength"),
        ("kind", "smudge", "brush.kind"),
        ("influence", -1.0, "brush.influence"),
        ("symmetry", "xw", "brush.symmetry"),
    ],
)
def test_bad_brush_values_name_their_parameter_and_change_nothing(name, value, parameter):
    settings = Settings()
    events = record(settings.brush.events.changed)
    with pytest.raises(ParameterError) as info:
        settings.brush.set(name, value)
    assert info.value.parameter == parameter
    assert settings.brush.brush == Brush(DEFAULT_BRUSH, radius=0.08) and not events


def test_update_is_all_or_nothing_and_names_the_bad_field():
    settings = Settings()
    with pytest.raises(ParameterError) as info:
        settings.update({"constraint_radius": 0.2, "l_max": -3})
    assert info.value.parameter == "l_max"
    assert settings.constraint_radius == 0.1 and settings.l_max == 8
    with pytest.raises(ParameterError) as info:
        settings.brush_weights = {"grab": [1.0, 2.0]}
    assert info.value.parameter == "brush_weights.grab"


def test_l_max_keeps_curves_and_common_weights_and_adds_defaults():
    settings = Settings()
    spline = settings.falloff
    settings.set_brush_weights("pinch", np.arange(10.0))
    settings.l_max = 4
    assert np.array_equal(settings.weights_for("pinch"), np.arange(6.0))
    settings.l_max = 6
    expected = EngineSettings(l_max=6).weights_for("pinch")
    expected[:6] = np.arange(6.0)
    assert np.array_equal(settings.weights_for("pinch"), expected)
    assert settings.falloff is spline  # it had the curves of l_max 4 and 6: unchanged
    assert set(needed_curves(10)) - set(spline.curve_keys())  # not yet there
    settings.l_max = 10
    assert set(needed_curves(10)) <= set(settings.falloff.curve_keys())
    # a new value with the old curves kept (values are immutable: the old one is unchanged)
    assert set(needed_curves(10)) - set(spline.curve_keys())
    for key in spline.curve_keys():
        assert all(map(np.array_equal, settings.falloff.curve(*key), spline.curve(*key)))


def test_assigning_a_profile_gives_a_spline_of_its_curves():
    settings = Settings()
    spline = settings.falloff
    before = spline.to_dict()
    version = spline.version
    events = record(settings.events.falloff)
    settings.falloff = KelvinletRadial(0.3)
    # a new value (the falloff is immutable, compared by content), the old one unchanged
    new = settings.falloff
    assert isinstance(new, SplineRadial) and new.eps == 1.0 and new != spline
    assert new.version > version and len(events) == 1 and spline.to_dict() == before
    rho = np.array([0.5, 1.0, 2.0])
    assert np.allclose(
        new.dimensionless("R", 2, rho), KelvinletRadial(1.0).dimensionless("R", 2, rho), 1e-3
    )
    settings.falloff = KelvinletRadial(1.0)  # the same curves: no change, no event
    assert settings.falloff is new and len(events) == 1
    with pytest.raises(ParameterError) as info:
        settings.falloff = "gaussian"
    assert info.value.parameter == "falloff"


def test_presets_round_trip_through_the_model():
    settings = Settings()
    preset = Preset(
        "p",
        Material.isotropic(2.0, 0.4),
        KelvinletRadial(1.0),
        6,
        brush=Brush("wrinkle", radius=0.05, influence=2.5, symmetry="x"),
    )
    settings.apply_preset(preset)
    assert settings.material == preset.material and settings.l_max == 6
    assert settings.brush.influence == 2.5 and settings.brush.kind == "wrinkle"
    again = Preset.from_dict(settings.preset("again").to_dict())
    assert again.brush == preset.brush and again.material == preset.material
    assert isinstance(again.falloff, SplineRadial)


@pytest.fixture
def sculptor():
    vertices, faces = icosphere(2)
    return Sculptor(vertices, faces)


def test_engine_link_feeds_the_sculptor_one_call_per_group(sculptor, monkeypatch):
    settings = Settings()
    link = EngineLink(settings, sculptor)
    calls = []
    real = sculptor.change_settings
    monkeypatch.setattr(sculptor, "change_settings", lambda **k: (calls.append(k), real(**k)))
    settings.material = Material.isotropic(1.0, 0.45)
    assert sculptor.settings.material == Material.isotropic(1.0, 0.45) and len(calls) == 1
    settings.update({"l_max": 4, "falloff": GaussianRadial(1.0)})
    assert len(calls) == 2 and sculptor.settings.l_max == 4
    assert set(calls[-1]) == {"falloff", "l_max", "brush_weights", "continued"}
    assert sculptor.settings.brush_weights == settings.brush_weights
    settings.constraint_radius = 0.2
    assert sculptor.settings.constraint_radius == 0.2
    # a curve edit (a drag step: a new falloff value) reaches the engine
    rho, value = settings.falloff.curve("R", 0)
    edited = settings.falloff.with_point_moved("R", 0, 2, float(rho[2]), float(value[2]) * 2)
    settings.set("falloff", edited, continued=True)
    assert len(calls) == 4 and calls[-1]["continued"]
    assert np.isclose(sculptor.settings.falloff.curve("R", 0)[1][2], value[2] * 2)
    link.attach(None)
    settings.material = Material.isotropic(1.0, 0.2)  # no engine: nothing to feed


def test_engine_refusal_restores_the_settings_and_reports(sculptor):
    settings = Settings()
    errors = []
    EngineLink(settings, sculptor, on_error=lambda p, e: errors.append((p, str(e))))
    sculptor.begin_stroke(Brush())
    settings.material = Material.isotropic(1.0, 0.45)  # refused during a stroke
    assert errors and errors[0][0] == "material" and "stroke" in errors[0][1]
    assert settings.material == sculptor.settings.material == Material.isotropic(1.0, 0.3)
    sculptor.cancel_stroke()


def test_pull_copies_engine_values_without_echo(sculptor):
    settings = Settings()
    link = EngineLink(settings, sculptor)
    sculptor.change_settings(material=Material.isotropic(3.0, 0.1))  # e.g. an undo in the engine
    log_before = len(sculptor.session()["operations"])
    events = record(settings.events.material)
    link.pull()
    assert settings.material == Material.isotropic(3.0, 0.1)
    assert events[0].source == "engine"
    assert len(sculptor.session()["operations"]) == log_before  # not sent back


def test_pen_settings_validate_and_emit():
    import pytest as _pytest

    from gogreen_core.interaction.settings import Settings
    from gogreen_core.validation import ParameterError

    settings = Settings()
    assert settings.pen.pressure_strength is True and settings.pen.pressure_radius is False
    seen = []
    settings.pen.events.lazy_radius.connect(lambda e: seen.append(e.value))
    settings.pen.lazy_radius = 12
    assert seen == [12.0]
    with _pytest.raises(ParameterError, match="spacing"):
        settings.pen.spacing = -1
    with _pytest.raises(ParameterError, match="pressure_radius"):
        settings.pen.pressure_radius = "yes"
