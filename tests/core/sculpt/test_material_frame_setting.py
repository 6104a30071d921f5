"""The ``material_frame`` setting ("world" or "surface") in every place settings live: the
engine's value, its session form, the session log, presets, the evented model, the CLI."""

import json

import numpy as np
import pytest

from gogreen_core.files.presets import Preset
from gogreen_core.interaction.settings import Settings
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.material import Material
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.operations import SETTINGS_CHANGES, operation_from_dict
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.validation import ParameterError


def test_world_is_the_default_and_a_bad_frame_is_refused_by_name() -> None:
    assert EngineSettings().material_frame == "world"
    with pytest.raises(ParameterError, match="material_frame"):
        EngineSettings(material_frame="object")


def test_session_settings_round_trip_and_old_files_read_as_world() -> None:
    value = EngineSettings(material_frame="surface")
    data = value.to_dict()
    assert data["material_frame"] == "surface"
    assert EngineSettings.from_dict(json.loads(json.dumps(data))) == value
    old = EngineSettings().to_dict()
    assert "material_frame" not in old  # older files stay as they were
    assert EngineSettings.from_dict(old).material_frame == "world"
    with pytest.raises(ParameterError, match=r"settings\.material_frame"):
        EngineSettings.from_dict({**data, "material_frame": 3})


def test_the_log_records_the_frame_with_the_material() -> None:
    change = SETTINGS_CHANGES["material"]
    op = change({"material": Material.isotropic(2.0, 0.2), "material_frame": "surface"})
    again = operation_from_dict(json.loads(json.dumps(op.to_dict())))
    assert isinstance(again, change) and again.values["material_frame"] == "surface"
    old = {"op": "material", "material": Material.isotropic(1.0, 0.3).to_dict()}
    parsed = operation_from_dict(old)
    assert isinstance(parsed, change) and parsed.values["material_frame"] == "world"
    assert "material_frame" not in change(parsed.values).to_dict()  # older files as they were


def test_sculptor_change_is_one_undo_step_and_replays() -> None:
    vertices, faces = icosphere(2)
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_settings(sculptor.settings.replace(material_frame="surface"))
    assert sculptor.settings.material_frame == "surface"
    sculptor.undo()
    assert sculptor.settings.material_frame == "world"
    sculptor.redo()
    session = sculptor.session()
    assert any(op.get("material_frame") == "surface" for op in session["operations"])


def test_presets_and_the_evented_model_carry_it() -> None:
    preset = Preset("p", Material.isotropic(1.0, 0.3), material_frame="surface")
    data = preset.to_dict()
    assert Preset.from_dict(json.loads(json.dumps(data))).material_frame == "surface"
    assert "material_frame" not in Preset("q", Material.isotropic(1.0, 0.3)).to_dict()
    with pytest.raises(ParameterError, match="material_frame"):
        Preset.from_dict({**data, "material_frame": "sideways"})
    model = Settings()
    assert model.material_frame == "world"
    model.apply_preset(preset)
    assert model.engine_settings.material_frame == "surface"
    assert model.preset("again").material_frame == "surface"
    with pytest.raises(ParameterError):
        model.material_frame = "diagonal"
    vertices, faces = icosphere(2)
    sculptor = Sculptor(vertices, faces)
    preset.apply(sculptor)
    assert sculptor.settings.material_frame == "surface"
    assert np.isfinite(sculptor.model_size)
