"""Presets: built-in files load and apply, round trips, bad files, atomic save."""

import dataclasses
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from gogreen_core import (
    Brush,
    Material,
    Preset,
    Sculptor,
    builtin_presets,
    load_preset,
    save_preset,
)
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.radial import KelvinletRadial

ROOT = Path(__file__).resolve().parents[3]


def _make_presets_module():
    spec = importlib.util.spec_from_file_location("make_presets", ROOT / "scripts/make_presets.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_builtin_presets_match_their_generator_and_apply():
    shipped = builtin_presets()
    expected = list(_make_presets_module().builtin().values())
    assert [p.name for p in shipped] == [p.name for p in expected]
    vertices, faces = icosphere(2)
    for have, want in zip(shipped, expected, strict=True):
        assert np.allclose(have.material.voigt, want.material.voigt, rtol=1e-9, atol=1e-12)
        assert have.brush == want.brush and have.l_max == want.l_max
        assert have.description
        sculptor = Sculptor(vertices, faces)
        have.apply(sculptor)
        assert sculptor.settings.material == have.material and sculptor.settings.l_max == have.l_max


def test_preset_round_trip_and_apply():
    preset = Preset(
        "test",
        Material.cubic(3.0, 1.5, 0.4),
        KelvinletRadial(1.0),
        l_max=6,
        brush_weights={"pinch": tuple(np.arange(8.0))},
        brush=Brush("twist", radius=0.05, symmetry="x"),
        description="d",
    )
    again = Preset.from_dict(json.loads(json.dumps(preset.to_dict())))
    assert again.material == preset.material and again.brush == preset.brush
    assert again.brush_weights == preset.brush_weights
    assert again.falloff.to_dict() == preset.falloff.to_dict()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("{", "not valid JSON"),
        ('{"format": "other"}', "not a GoGreen preset"),
        (
            '{"format": "gogreen-preset", "material": {"voigt": [[1]]}, "brush": {}, '
            '"falloff": {"type": "gaussian", "eps": 1}}',
            r"material\.voigt must be a 6×6 matrix",
        ),
        ('{"format": "gogreen-preset", "falloff": {"type": "gaussian", "eps": 1}}', "material"),
    ],
)
def test_bad_preset_files_are_rejected_naming_the_file(tmp_path, text, message):
    path = tmp_path / "broken.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as info:
        load_preset(path)
    assert "broken.json" in str(info.value)


def test_a_failed_save_keeps_the_old_file(tmp_path, monkeypatch):
    path = tmp_path / "p.json"
    save_preset(builtin_presets()[0], path)
    before = path.read_bytes()

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("gogreen_core.mesh.mesh_io.atomic.os.replace", broken)
    with pytest.raises(ValueError, match=r"p\.json"):
        save_preset(builtin_presets()[1], path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.json"]


def test_a_preset_is_replaced_like_a_dataclass():
    preset = builtin_presets()[0]
    renamed = dataclasses.replace(preset, name="mine", brush=Brush("twist"))
    assert renamed.name == "mine" and renamed.brush == Brush("twist")
    assert renamed.settings == preset.settings and renamed.l_max == preset.l_max
