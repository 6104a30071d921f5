"""The engine's settings as one immutable value: checked once, compared by content, shared by
the evented model, presets, sessions and the sculptor."""

import json

import numpy as np
import pytest

from gogreen_core import EngineSettings, Material, Preset, Sculptor
from gogreen_core.interaction.settings import EngineLink, Settings
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, SplineRadial
from gogreen_core.validation import ParameterError

CUBIC = Material.cubic(3.0, 1.5, 0.4)


@pytest.mark.parametrize(
    ("changes", "parameter"),
    [
        ({"material": "steel"}, "material"),
        ({"falloff": 1.0}, "falloff"),
        ({"l_max": -1}, "l_max"),
        ({"l_max": 4, "brush_weights": {"grab": [1.0, 2.0]}}, "brush_weights.grab"),
        ({"brush_weights": {"grab": [float("nan")] * 10}}, "brush_weights.grab"),
        ({"constraint_radius": 0.0}, "constraint_radius"),
    ],
)
def test_every_field_is_checked_by_the_constructor(changes, parameter):
    with pytest.raises(ParameterError) as info:
        EngineSettings(**changes)
    assert info.value.parameter == parameter
    with pytest.raises(ParameterError) as info:  # replace checks as the constructor does
        EngineSettings().replace(**changes)
    assert info.value.parameter == parameter


def test_values_compare_by_content_and_do_not_change():
    spline = SplineRadial.from_profile(KelvinletRadial(2.0), 6)
    weights = np.linspace(1.0, 2.0, 8)
    a = EngineSettings(CUBIC, spline, 6, 0.2, {"pinch": weights})
    b = EngineSettings(
        CUBIC, SplineRadial.from_profile(KelvinletRadial(1.0), 6), 6, 0.2, {"pinch": weights}
    )
    assert a == b and a is not b and a != a.replace(constraint_radius=0.3)
    assert a.falloff.eps == 1.0  # the shape, at ε = 1
    weights[0] = 5.0
    assert a == b and a.weights_for("pinch")[0] == 1.0
    with pytest.raises(TypeError):
        a.brush_weights["pinch"] = (3.0,)  # type: ignore[index]  # read-only
    edited = a.falloff.with_curves({("R", 0): a.falloff.curve("R", 2)})  # a new value
    assert edited != a.falloff and a == b
    assert EngineSettings.from_dict(json.loads(json.dumps(a.to_dict()))) == a


def test_the_sculptor_takes_one_value_or_its_fields_not_both():
    vertices, faces = icosphere(2)
    value = EngineSettings(material=CUBIC, l_max=6)
    sculptor = Sculptor(vertices, faces, settings=value)
    assert sculptor.settings == value == Sculptor(vertices, faces, material=CUBIC, l_max=6).settings
    with pytest.raises(TypeError, match="not both"):
        Sculptor(vertices, faces, settings=value, l_max=4)
    sculptor.apply_settings(value.replace(falloff=KelvinletRadial(1.0), constraint_radius=0.2))
    assert sculptor.history.undo_labels == ["falloff", "constraint radius"]
    sculptor.apply_settings(sculptor.settings)  # the same value: no step
    assert len(sculptor.history.undo_labels) == 2
    sculptor.undo()
    sculptor.undo()
    assert sculptor.settings == value


def test_model_presets_and_engine_share_the_value():
    vertices, faces = icosphere(2)
    model = Settings()
    sculptor = Sculptor(vertices, faces, **model.sculptor_options())
    EngineLink(model, sculptor)
    assert sculptor.settings == model.engine_settings
    preset = Preset("p", CUBIC, GaussianRadial(1.0), 4)
    model.apply_preset(preset)
    assert sculptor.settings == model.engine_settings
    assert preset.engine_settings(sculptor.settings).agrees(sculptor.settings, ["material"])
    with pytest.raises(ParameterError) as info:
        Preset("bad", CUBIC, l_max=99)
    assert info.value.parameter == "l_max"
