"""Each engine setting is declared once (gogreen_core/sculpt/setting_table.py): the engine's
value, the app's settings model, presets, session files and the command line are made from the
table, so that a new setting is one row (plus its typed line on EngineSettings)."""

import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import trimesh

from gogreen_core.files.presets import Preset
from gogreen_core.interaction.batch import _parser
from gogreen_core.interaction.settings import ENGINE_FIELDS, Settings
from gogreen_core.sculpt import engine_settings
from gogreen_core.sculpt.engine_settings import SETTING_GROUPS, EngineSettings
from gogreen_core.sculpt.operations import SETTINGS_CHANGES
from gogreen_core.sculpt.setting_table import PLACES, SETTINGS, Setting, rows

ROOT = Path(__file__).resolve().parents[3]


def test_every_place_has_the_tables_fields():
    names = {place: [s.name for s in rows(place)] for place in PLACES}
    assert [f for f in EngineSettings.__dataclass_fields__] == names["engine"]
    assert set(names["app"]) <= set(Settings.fields) and list(ENGINE_FIELDS) == names["app"]
    assert set(Preset("p").to_dict()) == {"format", "version", "name", "description", "brush"} | {
        s.name for s in rows("preset") if s.since == 1
    }
    assert set(EngineSettings().to_dict()) == {s.name for s in rows("session") if s.since == 1}
    assert [g[0] for g in SETTING_GROUPS] == list(SETTINGS_CHANGES)
    flags = _parser()._subparsers._group_actions[0].choices["deform"]._option_string_actions
    scalar = [s for s in rows("cli") if s.type not in ("material", "falloff", "weights")]
    assert scalar and all(s.flag in flags for s in scalar)


def test_engine_settings_refuses_a_row_without_its_typed_line():
    extra = Setting("grain", "choice", "world", "a test setting", choices=("world", "surface"))
    with pytest.raises(TypeError, match="grain"):
        engine_settings._check_fields((*SETTINGS, extra))


# A new engine setting as a developer adds it: one row in the table, its typed line on
# EngineSettings; then every place has it, without another edit.
ADDED_ROW = """    Setting(
        "grain",
        "choice",
        "world",
        "whether the material's axes follow the surface",
        since=6,
        places=("engine", "app", "preset", "session", "cli"),
        choices=("world", "surface"),
    ),"""
ADDED_LINE = '    grain: str = field(default_factory=_initial("grain"))\n'

CHECKS = """
import json, sys
import numpy as np
from gogreen_core.files.presets import Preset
from gogreen_core.interaction.batch import main
from gogreen_core.interaction.settings import EngineLink, Settings
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.engine_settings import SETTING_GROUPS, EngineSettings
from gogreen_core.sculpt.operations import operation_from_dict
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import parse_session
from gogreen_core.validation import ParameterError

def refused(call, parameter):
    try:
        call()
    except ParameterError as exc:
        assert exc.parameter == parameter, (exc.parameter, parameter)
        return
    raise AssertionError(f"not refused: {parameter}")

# the engine's value: default, check naming the field, JSON only when not the default
assert EngineSettings().grain == "world" and ("grain",) in SETTING_GROUPS
surface = EngineSettings(grain="surface")
refused(lambda: EngineSettings(grain="up"), "grain")
assert "grain" not in EngineSettings().to_dict() and surface.to_dict()["grain"] == "surface"
assert EngineSettings.from_dict(surface.to_dict()) == surface
refused(lambda: EngineSettings.from_dict({**surface.to_dict(), "grain": 3}), "settings.grain")
# the sculptor: an undo step and a session record of its own, replayed
vertices, faces = icosphere(2)
sculptor = Sculptor(vertices, faces)
sculptor.change_settings(grain="surface")
session = json.loads(json.dumps(sculptor.session()))
assert session["operations"] == [{"op": "grain", "grain": "surface"}], session["operations"]
again = Sculptor.from_session(session, vertices, faces)
again.replay(parse_session(session))
assert again.settings.grain == "surface"
sculptor.undo()
assert sculptor.settings.grain == "world"
refused(lambda: operation_from_dict({"op": "grain", "grain": "up"}, "operations[0]"),
        "operations[0].grain")
# the app's model: a field with events, checked, fed to the engine
model, seen = Settings(), []
model.events.grain.connect(lambda e: seen.append(e.value))
link = EngineLink(model, sculptor)
model.grain = "surface"
assert seen == ["surface"] and sculptor.settings.grain == "surface"
refused(lambda: model.set("grain", "up"), "grain")
# presets
preset = Preset.from_dict(json.loads(json.dumps(Preset("p", grain="surface").to_dict())))
assert preset.grain == "surface" and model.preset().grain == "surface"
model.grain = "world"
model.apply_preset(preset)
assert model.grain == "surface"
# the command line
mesh, out = sys.argv[1], sys.argv[2]
assert main(["deform", mesh, "-o", out + ".obj", "--center", "0", "0", "1", "--delta", "0", "0",
             "0.1", "--grain", "surface", "--session-out", out + ".json", "-q"]) == 0
assert json.load(open(out + ".json"))["settings"]["grain"] == "surface"
print("ok")
"""


def test_a_new_setting_is_one_row_and_its_typed_line(tmp_path):
    copy = tmp_path / "gogreen_core"
    shutil.copytree(ROOT / "gogreen_core", copy, ignore=shutil.ignore_patterns("__pycache__"))
    table = copy / "sculpt" / "setting_table.py"
    text = table.read_text()
    end = text.index("\n)", text.index("SETTINGS: tuple[Setting, ...] = ("))  # the table's end
    table.write_text(text[:end] + "\n" + ADDED_ROW + text[end:])
    settings_module = copy / "sculpt" / "engine_settings.py"
    text = settings_module.read_text()
    typed = re.finditer(r"^    \w+: .*_initial\(\"\w+\"\)\)$", text, re.M)
    anchor = max(m.end() for m in typed) + 1  # after the last typed line: the table's order
    settings_module.write_text(text[:anchor] + ADDED_LINE + text[anchor:])
    mesh = tmp_path / "ico.obj"
    trimesh.creation.icosphere(2).export(mesh)
    script = tmp_path / "checks.py"
    script.write_text(textwrap.dedent(CHECKS))
    result = subprocess.run(
        [sys.executable, str(script), str(mesh), str(tmp_path / "out")],
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(tmp_path)},
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0 and result.stdout.strip().endswith("ok"), result.stderr[-3000:]
