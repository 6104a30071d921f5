"""Session files written by earlier versions (tests/fixtures/sessions, recorded with the code
of each version: see record.py there) replay with today's arithmetic within 1e-4 of their
largest motion, or are refused naming the operation that cannot be replayed."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from gogreen_core.files.recovery import journal_session, read_journal, recover
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import SESSION_VERSION, parse_session, upgrade_session
from gogreen_core.validation import ParameterError

FIXTURES = Path(__file__).parents[2] / "fixtures" / "sessions"
JOURNAL = Path(__file__).parents[2] / "fixtures" / "journal_v1"


def _session(name: str) -> dict:
    return json.loads((FIXTURES / f"{name}.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    ("name", "version"),
    [("version1_grabs", 1), ("version2", 2), ("version3", 3), ("version4", 4)],
)
def test_an_older_session_replays_within_its_tolerance(name, version):
    data = _session(name)
    assert data["version"] == version
    recorded = np.load(FIXTURES / f"{name}.npz")
    start, final = recorded["vertices"], recorded["final"]
    sculptor = Sculptor.from_session(data, start, recorded["faces"])
    sculptor.replay(parse_session(data))
    motion = np.abs(final[: len(start)] - start).max()
    assert motion > 0.05  # the session moves the model
    assert sculptor.vertices.shape == final.shape
    assert np.abs(sculptor.vertices - final).max() <= 1e-4 * motion
    # it records itself again as a session of today's version, which replays the same
    again = sculptor.session()
    assert again["version"] == SESSION_VERSION
    replayed = Sculptor.from_session(again, start, recorded["faces"])
    replayed.replay(parse_session(again))
    assert np.abs(replayed.vertices - sculptor.vertices).max() <= 1e-12 * motion


@pytest.mark.parametrize(
    ("name", "operation", "words"),
    [
        ("version1", 3, "twist brush's amount"),
        ("version2_wrinkle", 1, "wrinkle brush of version-2 sessions"),
    ],
)
def test_a_session_that_cannot_be_replayed_is_refused_naming_the_operation(name, operation, words):
    with pytest.raises(ParameterError, match=rf"operations\[{operation}\]") as info:
        parse_session(_session(name))
    assert info.value.parameter == f"operations[{operation}]"
    assert words in str(info.value)


def test_version_1_undo_that_would_now_undo_a_settings_change_is_refused():
    data = _session("version1_grabs")
    ops = data["operations"]
    material = next(op for op in ops if op["op"] == "material")
    # a settings change right before an undo: version 1 undid the stroke before it
    data["operations"] = [ops[0], material, {"op": "undo"}]
    with pytest.raises(ParameterError, match=r"operations\[2\] \(undo\)"):
        parse_session(data)
    data["operations"] = [ops[0], {"op": "undo"}, material, {"op": "redo"}]
    assert len(parse_session(data).operations) == 4  # the same step either way


def test_upgrades_drop_the_legacy_wrinkle_weights_and_make_old_influence_explicit():
    data = _session("version2")
    assert "degree_weights" in data["settings"]
    upgraded = upgrade_session(data)
    assert upgraded["version"] == SESSION_VERSION
    assert "degree_weights" not in upgraded["settings"]
    falloffs = [op for op in upgraded["operations"] if op["op"] == "falloff"]
    assert falloffs and all("degree_weights" not in op for op in falloffs)
    strokes = [op for op in upgraded["operations"] if op["op"] == "stroke"]
    assert all(op["brush"]["influence"] == 4.0 for op in strokes)
    assert data["version"] == 2  # the file's object is not changed


def test_a_current_session_naming_the_legacy_weights_is_refused():
    data = upgrade_session(_session("version4"))
    data["settings"] = {**data["settings"], "degree_weights": None}
    with pytest.raises(ParameterError, match="degree_weights"):
        parse_session(data)


def test_fixtures_are_small():
    paths = [*FIXTURES.iterdir(), *JOURNAL.iterdir()]
    assert all(path.stat().st_size < 200_000 for path in paths)


@pytest.mark.parametrize("budget", [0.0, float("inf")], ids=["from its checkpoint", "from start"])
def test_a_journal_of_the_previous_version_recovers_within_its_tolerance(tmp_path, budget):
    """A journal written by the previous version (tests/fixtures/journal_v1, recorded with
    70b041d by record.py there: grab, falloff, twist, checkpoint, wrinkle, pin, drag,
    biscale) recovers with today's arithmetic, from its checkpoint or from its start."""
    directory = tmp_path / "journal"
    shutil.copytree(JOURNAL, directory)
    (directory / "final.npz").unlink()
    (directory / "record.py").unlink()
    recorded = np.load(JOURNAL / "final.npz")
    recovery = recover(directory, budget=budget)
    assert not recovery.notes
    motion = np.abs(recorded["final"] - recorded["start"]).max()
    assert np.abs(recovery.mesh.vertices - recorded["final"]).max() <= 1e-4 * motion
    assert len(recovery.sculptor.constraint_points) == 1
    session = journal_session(read_journal(directory))
    assert session["version"] == SESSION_VERSION
    assert "degree_weights" not in session["settings"]
    assert len(parse_session(session).operations) == 7


def test_an_affine_stroke_of_a_version_5_session_replays_with_the_falloff_it_had():
    """Version 6 made the affine brushes local: a stroke recorded before is renamed to the
    replay-only brush with the settings' falloff itself, and its ω are the offered brush's."""
    from gogreen_core.sculpt.brushes import REPLAY_KINDS, brush_type

    data = {
        "version": 5,
        "operations": [
            {"op": "stroke", "brush": {"kind": "scale"}},
            {"op": "stroke", "brush": {"kind": "grab"}},
        ],
    }
    upgraded = upgrade_session(data)["operations"]
    assert upgraded[0]["brush"]["kind"] == REPLAY_KINDS["scale"] == "scale_wide"
    assert upgraded[1]["brush"]["kind"] == "grab"
    wide, local = brush_type("scale_wide"), brush_type("scale")
    assert wide.weights_kind == "scale" and wide.radial_key == "" and local.radial_key == "scale"
