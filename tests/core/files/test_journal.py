"""The crash-recovery journal (gogreen_core.files.journal) and recovery
(gogreen_core.files.recovery): where journals live, locking, clean close, restart on save, exact
recovery from the start and from checkpoints, the undo history after recovery, and every kind of
damage (README, "Crash recovery")."""

from __future__ import annotations

import errno
import json
import os
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import journal_script
import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.files.journal import JOURNAL_FILE, Journal, recovery_root
from gogreen_core.files.journal_format import SETTINGS_WORK, JournalLock
from gogreen_core.files.journal_format import state_home as journal_state_home
from gogreen_core.files.recovery import (
    JournalError,
    discard,
    find_journal,
    journal_session,
    list_journals,
    read_journal,
    recover,
)
from gogreen_core.mesh.mesh_io import MeshData, save_mesh
from gogreen_core.sculpt.checkpoint import CheckpointError, read_checkpoint
from gogreen_core.sculpt.constraints import ConstraintSet
from gogreen_core.sculpt.sculptor import capture_state, restore_state
from gogreen_core.sculpt.session import parse_session


@pytest.fixture
def mesh() -> MeshData:
    return journal_script.mesh()


def stroke(sculptor: Sculptor, k: int) -> None:
    vertices = sculptor.vertices
    center = vertices[(37 * k) % len(vertices)].copy()
    delta = 0.01 * np.array([1.0, 0.5 * (k % 3), -0.3])
    sculptor.apply_brush(
        Brush("grab", radius=0.2), [BrushEvent(center + i * delta, delta) for i in range(6)]
    )


def journaled(mesh: MeshData, root: Path, **options) -> tuple[Sculptor, Journal]:
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    return sculptor, Journal(sculptor, mesh, root=root, **options)


def checkpoint(journal: Journal) -> None:
    """A checkpoint now, on disk before going on (the journal skips a checkpoint when a newer
    one is queued behind it: the tests want each one)."""
    assert journal.checkpoint()
    journal.flush()


def crash(journal: Journal) -> Path:
    """Leave the journal as a killed process would (all written, lock dropped)."""
    journal.flush()
    directory = journal.directory
    journal.close(remove=False)
    return directory


def same_state(a: Sculptor, b: Sculptor) -> bool:
    return (
        np.array_equal(a.vertices, b.vertices)
        and np.array_equal(a.constraint_points, b.constraint_points)
        and a.settings.to_dict() == b.settings.to_dict()
    )


# -- hooks -------------------------------------------------------------------------------------
def test_the_log_tells_its_listeners_every_change(mesh):
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    seen = []
    unsubscribe = sculptor.subscribe(
        lambda kind, item, n: seen.append((kind, type(item).__name__, n))
    )
    stroke(sculptor, 0)
    sculptor.change_settings(material=Material.isotropic(1, 0.2))
    sculptor.change_settings(material=Material.isotropic(1, 0.1), continued=True)
    sculptor.undo()
    assert seen == [("event", "BrushEvent", 0)] * 6 + [
        ("append", "Stroke", 1),
        ("append", "MaterialChange", 2),
        ("replace", "MaterialChange", 2),
        ("append", "Undo", 3),
    ]
    unsubscribe()
    stroke(sculptor, 1)
    assert len(seen) == 10


def test_a_state_continues_bit_for_bit_pins_included(mesh):
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    for i in (0, 40, 90, 200):
        sculptor.add_constraint(mesh.vertices[i])
    sculptor.drag_constraint(0, [0.01, 0, 0])
    sculptor.drag_constraint(2, [0, 0.02, 0])
    sculptor.remove_constraint(1)
    stroke(sculptor, 1)
    # why the pins' solver state is saved: rebuilt from the points it rounds differently
    live = capture_state(sculptor).pins
    rebuilt = ConstraintSet(
        restore_state(capture_state(sculptor), mesh.faces)._pins.constraints.kernel
    )
    for point in live[0]:
        rebuilt.add(point)
    assert not np.array_equal(rebuilt.inverse, live[2])
    copy = restore_state(capture_state(sculptor), mesh.faces)
    assert copy.model_size == sculptor.model_size and np.array_equal(copy.origin, sculptor.origin)
    assert not copy.history.can_undo and copy.operations == []
    for s in (sculptor, copy):
        s.drag_constraint(1, [0.004, 0.002, -0.01])
        s.apply_brush(Brush("grab", symmetry="x"), [BrushEvent(mesh.vertices[3], [0.01, 0.02, 0])])
    assert same_state(sculptor, copy)


def test_history_done_counts_steps_not_merges_nor_evictions():
    from gogreen_core.sculpt.history import History

    history = History(max_bytes=2000)
    vertices = np.zeros((40, 3))
    for k in range(6):
        history.record_rows("s", np.arange(len(vertices)), vertices, vertices + k + 1)
    assert history.done == 6 and len(history.undo_labels) < 6  # some were evicted
    history.record_rows("s", np.arange(len(vertices)), vertices, vertices + 9, merge=True)
    history.undo(vertices)
    assert history.done == 5
    history.redo(vertices)
    assert history.done == 6


# -- where and how -----------------------------------------------------------------------------
def test_journals_live_in_the_state_home_private_to_the_user(mesh, state_home, monkeypatch):
    assert recovery_root() == state_home / "gogreen-sculpt" / "recovery"
    _, journal = journaled(mesh, None)
    assert journal.directory.parent == recovery_root()
    for folder in (recovery_root().parent, recovery_root(), journal.directory):
        assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert stat.S_IMODE((journal.directory / JOURNAL_FILE).stat().st_mode) == 0o600
    journal.close()
    monkeypatch.delenv("XDG_STATE_HOME")
    monkeypatch.setenv("HOME", str(state_home / "home"))
    assert journal_state_home() == state_home / "home" / ".local" / "state"
    monkeypatch.setenv("XDG_STATE_HOME", "relative/path")  # the spec says: ignore it
    assert journal_state_home() == state_home / "home" / ".local" / "state"


def test_each_record_is_one_checksummed_line_written_before_the_call_returns(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path)
    stroke(sculptor, 0)
    lines = (journal.directory / JOURNAL_FILE).read_bytes().splitlines()  # no flush needed
    assert len(lines) == 2
    crc, payload = lines[1].split(b" ", 1)
    record = json.loads(payload)
    assert record["seq"] == 1 and record["kind"] == "append" and record["op"]["op"] == "stroke"
    assert record["op"] == json.loads(json.dumps(sculptor.operations[0].to_dict()))
    assert len(crc) == 8
    journal.close()


def test_a_clean_close_removes_the_journal_and_the_lock_keeps_others_out(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path)
    stroke(sculptor, 0)
    journal.flush()
    assert JournalLock.acquire(journal.directory) is None  # another instance cannot take it
    (info,) = list_journals(tmp_path)
    assert info.in_use and str(os.getpid()) in info.status()
    with pytest.raises(JournalError, match="in use"):
        recover(journal.directory)
    with pytest.raises(JournalError, match="in use"):
        discard(journal.directory)
    journal.close()
    assert list(tmp_path.iterdir()) == []


def test_two_instances_on_one_file_write_two_journals(mesh, tmp_path):
    a, first = journaled(mesh, tmp_path)
    b, second = journaled(mesh, tmp_path)
    assert first.directory != second.directory
    stroke(a, 0)
    stroke(b, 5)
    for journal in (first, second):
        crash(journal)
    recovered = [recover(info.directory) for info in list_journals(tmp_path)]
    assert sorted(r.records for r in recovered) == [1, 1]
    assert {r.sculptor.vertices.tobytes() for r in recovered} == {
        a.vertices.tobytes(),
        b.vertices.tobytes(),
    }


def test_a_save_starts_a_fresh_journal(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    sculptor.add_constraint(mesh.vertices[5])
    sculptor.drag_constraint(0, [0.02, 0, 0])
    for k in range(3):
        stroke(sculptor, k)
        checkpoint(journal)
    assert len(list(journal.directory.glob("checkpoint-*.bin"))) == 3
    journal.restart()  # what the app does after a save
    for k in range(3, 5):
        stroke(sculptor, k)
        checkpoint(journal)
    sculptor.drag_constraint(0, [0.01, 0.01, 0])
    checkpoint(journal)
    directory = crash(journal)
    assert len(list(directory.glob("base-*.npz"))) == 1
    assert sorted(p.name for p in directory.glob("checkpoint-*.bin")) == [
        "checkpoint-1.bin",
        "checkpoint-2.bin",
        "checkpoint-3.bin",
    ]
    recovery = recover(directory, budget=float("inf"))
    assert recovery.records == 3 and recovery.start == 0
    assert same_state(recovery.sculptor, sculptor)


# -- recovery ----------------------------------------------------------------------------------
def test_recovery_from_the_start_rebuilds_the_whole_undo_history(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    for k in range(5):
        stroke(sculptor, k)
        checkpoint(journal)
    sculptor.undo()
    directory = crash(journal)
    recovery = recover(directory, budget=float("inf"))
    recovered = recovery.sculptor
    assert recovery.start == 0 and recovery.replayed == 6
    assert same_state(recovered, sculptor)
    assert recovered.history.undo_labels == sculptor.history.undo_labels
    for s in (sculptor, recovered):
        s.redo()
        s.undo()
        s.undo()
    assert same_state(recovered, sculptor)


def test_recovery_from_a_checkpoint_is_exact_and_keeps_the_history_after_it(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    for k in range(4):
        stroke(sculptor, k)
        checkpoint(journal)
    sculptor.change_settings(material=Material.isotropic(1, 0.45))
    checkpoint(journal)
    stroke(sculptor, 4)
    checkpoint(journal)
    directory = crash(journal)
    recovery = recover(directory, budget=0)
    assert recovery.start == 6 and recovery.replayed == 0  # the newest checkpoint
    assert same_state(recovery.sculptor, sculptor)
    recovery.release()
    recovery = recover(directory, budget=SETTINGS_WORK + 6 * len(mesh.vertices))
    assert recovery.start == 4 and recovery.replayed == 2  # the oldest that fits the budget
    assert recovery.sculptor.history.undo_labels == ["material", "Wide grab stroke"]
    for s in (sculptor, recovery.sculptor):
        s.undo()
        s.undo()
        stroke(s, 9)
    assert same_state(recovery.sculptor, sculptor)


def test_a_checkpoint_the_records_undo_past_is_not_used(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    for k in range(5):
        stroke(sculptor, k)
        if k == 3:
            checkpoint(journal)  # after record 4
    for _ in range(3):
        sculptor.undo()  # back past it
    directory = crash(journal)
    assert [p.name for p in directory.glob("checkpoint-*.bin")] == ["checkpoint-4.bin"]
    recovery = recover(directory, budget=0)
    assert recovery.start == 0 and recovery.records == 8
    assert same_state(recovery.sculptor, sculptor)


def test_a_continued_drag_across_a_checkpoint(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    sculptor.change_settings(material=Material.isotropic(1, 0.2))
    journal.checkpoint()  # in the middle of a slider drag
    for nu in (0.15, 0.1, 0.05):
        sculptor.change_settings(material=Material.isotropic(1, nu), continued=True)
    sculptor.undo()
    stroke(sculptor, 2)
    directory = crash(journal)
    for budget in (0, float("inf")):
        recovery = recover(directory, budget=budget)
        assert same_state(recovery.sculptor, sculptor)
        recovery.release()


def test_the_session_of_a_journal_replays_to_the_recovered_mesh(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path)
    sculptor.add_constraint(mesh.vertices[100])
    sculptor.drag_constraint(0, [0.0, 0.02, 0.0])
    sculptor.change_settings(material=Material.isotropic(1, 0.2))
    sculptor.change_settings(material=Material.isotropic(1, 0.1), continued=True)
    stroke(sculptor, 3)
    sculptor.undo()
    directory = crash(journal)
    session = journal_session(read_journal(directory))
    assert session["operations"] == json.loads(json.dumps(sculptor.session()["operations"]))
    replayed = Sculptor.from_session(parse_session(session), mesh.vertices, mesh.faces)
    replayed.replay(parse_session(session))
    assert same_state(replayed, sculptor)


# -- damaged journals --------------------------------------------------------------------------
def damaged(mesh: MeshData, root: Path, strokes: int = 6, checkpoints: bool = False):
    sculptor, journal = journaled(mesh, root, auto_checkpoint=False)
    states = [sculptor.vertices.copy()]
    for k in range(strokes):
        stroke(sculptor, k)
        states.append(sculptor.vertices.copy())
        if checkpoints:
            checkpoint(journal)
    return sculptor, crash(journal), states


def test_a_record_cut_off_by_the_crash_is_dropped_and_said(mesh, tmp_path):
    _, directory, states = damaged(mesh, tmp_path)
    path = directory / JOURNAL_FILE
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 40])
    recovery = recover(directory)
    assert recovery.records == 5 and np.array_equal(recovery.mesh.vertices, states[5])
    (note,) = recovery.notes
    assert "record 6 was cut off" in note and "the 5 records before it are kept" in note


def test_a_corrupt_record_drops_it_and_what_follows(mesh, tmp_path):
    _, directory, states = damaged(mesh, tmp_path)
    path = directory / JOURNAL_FILE
    lines = path.read_bytes().split(b"\n")
    lines[3] = lines[3].replace(b'"center":[', b'"center":[9')  # record 3, checksum now wrong
    path.write_bytes(b"\n".join(lines))
    recovery = recover(directory)
    assert recovery.records == 2 and np.array_equal(recovery.mesh.vertices, states[2])
    assert "record 3 is corrupt (checksum mismatch): it and the 3 after it" in recovery.notes[0]
    recovery.release()
    info = list_journals(tmp_path)[0]
    assert info.operations == 2 and "corrupt" in info.status()


@pytest.mark.parametrize("damage", ["corrupt", "truncated", "empty"])
def test_a_damaged_checkpoint_is_skipped_for_an_older_one(mesh, tmp_path, damage):
    _, directory, states = damaged(mesh, tmp_path, checkpoints=True)
    newest = directory / "checkpoint-6.bin"
    data = bytearray(newest.read_bytes())
    if damage == "corrupt":
        data[len(data) // 2] ^= 0x40  # one bit flipped in the vertices
    elif damage == "truncated":
        data = data[: len(data) // 2]
    else:
        data = b""
    newest.write_bytes(bytes(data))
    with pytest.raises(CheckpointError):
        read_checkpoint(newest)
    recovery = recover(directory, budget=0)
    assert recovery.start == 5 and recovery.records == 6
    assert np.array_equal(recovery.mesh.vertices, states[6])
    expected = {
        "corrupt": "checksum mismatch",
        "truncated": "cut short",
        "empty": "not a checkpoint",
    }
    assert any(
        "checkpoint after record 6 not used" in n and expected[damage] in n for n in recovery.notes
    )


def test_a_missing_base_copy_uses_the_document_file_or_a_checkpoint(mesh, tmp_path):
    document = tmp_path / "model.ply"
    save_mesh(mesh, document)  # binary PLY: the same float64 vertices
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    journal = Journal(sculptor, mesh, document=str(document), root=tmp_path / "j")
    for k in range(4):
        stroke(sculptor, k)
        checkpoint(journal)
    directory = crash(journal)
    next(directory.glob("base-*.npz")).unlink()
    recovery = recover(directory, budget=float("inf"))
    assert recovery.start == 0 and np.array_equal(recovery.mesh.vertices, sculptor.vertices)
    assert "is missing: the document's file" in recovery.notes[0]
    recovery.release()
    # the file changed since (the same topology): the newest checkpoint, on the file's faces
    changed = mesh.copy()
    changed.vertices = changed.vertices * 1.5
    save_mesh(changed, document)
    recovery = recover(directory, budget=float("inf"))
    assert recovery.start == 2 and np.array_equal(recovery.mesh.vertices, sculptor.vertices)
    assert "changed since" in recovery.notes[0]  # the oldest checkpoint kept: 2
    recovery.release()
    # nothing left to build the mesh from: said, and the session can still be written
    document.unlink()
    with pytest.raises(JournalError, match=r"nothing to rebuild the mesh from.*--session"):
        recover(directory)
    assert len(journal_session(read_journal(directory))["operations"]) == 4


def test_a_journal_from_a_newer_version_is_read_as_far_as_understood(mesh, tmp_path):
    _, directory, states = damaged(mesh, tmp_path, strokes=3)
    path = directory / JOURNAL_FILE
    lines = path.read_bytes().split(b"\n")
    header = json.loads(lines[0].split(b" ", 1)[1])
    header["version"] = 7
    future = {"seq": 4, "kind": "append", "n": 4, "t": 0.0, "d": 4, "op": {"op": "smooth"}}
    from gogreen_core.files.journal_format import frame

    lines[0] = frame(json.dumps(header).encode())[:-1]
    lines[-1] = frame(json.dumps(future).encode())
    path.write_bytes(b"\n".join(lines))
    recovery = recover(directory)
    assert recovery.records == 3 and np.array_equal(recovery.mesh.vertices, states[3])
    assert "newer GoGreen Sculpt (journal version 7" in recovery.notes[0]
    assert "record 4 holds an operation this version cannot read" in recovery.notes[1]


def test_a_read_only_journal_stops_writing_says_so_once_and_sculpting_goes_on(
    mesh, tmp_path, monkeypatch
):
    import gogreen_core.files.journal as journal_module
    import gogreen_core.sculpt.checkpoint as checkpoint_module

    sculptor, journal = journaled(mesh, tmp_path, checkpoint_work=1)
    for k in range(3):
        stroke(sculptor, k)
        journal.flush()

    def read_only(*_args, **_kwargs):
        raise OSError(errno.EROFS, "Read-only file system")

    # the file system turns read-only (as after a disk error): checkpoints, then records fail
    monkeypatch.setattr(checkpoint_module, "atomic_write", read_only)
    stroke(sculptor, 3)
    journal.flush()
    (problem,) = journal.take_problems()
    assert "checkpoints cannot be written (Read-only file system)" in problem
    assert journal.active  # records still go in
    monkeypatch.setattr(journal_module, "write_all", read_only)
    for k in range(4, 8):
        stroke(sculptor, k)  # never raises, never waits
    (problem,) = journal.take_problems()
    assert "journal stopped: Read-only file system" in problem and "until you save" in problem
    assert journal.take_problems() == [] and not journal.active
    assert len(sculptor.operations) == 8
    monkeypatch.undo()
    directory = crash(journal)
    recovery = recover(directory, budget=0)
    assert recovery.records == 4 and recovery.start == 3  # the newest checkpoint written


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders anyway")
def test_a_read_only_state_folder_means_no_journal_and_one_message(mesh, tmp_path):
    tmp_path.chmod(0o500)
    try:
        sculptor, journal = journaled(mesh, tmp_path / "recovery")
        stroke(sculptor, 0)
        (problem,) = journal.take_problems()
        assert "Crash recovery is off" in problem and not journal.active
    finally:
        tmp_path.chmod(0o700)


def test_a_read_only_state_folder_at_start(mesh, tmp_path):
    blocker = tmp_path / "state"
    blocker.write_text("a file where the folder should be")  # works for root too
    sculptor, journal = journaled(mesh, blocker / "gogreen-sculpt" / "recovery")
    stroke(sculptor, 0)
    (problem,) = journal.take_problems()
    assert "Crash recovery is off: cannot write the journal" in problem
    assert not journal.active and journal.directory is None
    journal.close()


def test_a_full_disk_while_sculpting(tmp_path):
    """A real short write: the child's files may not grow past a limit (RLIMIT_FSIZE), so the
    kernel writes part of a record, then refuses (EFBIG), as with a full disk."""
    child = textwrap.dedent(
        f"""
        import json, resource, signal, sys
        sys.path.insert(0, {str(Path(__file__).resolve().parents[2] / "helpers")!r})
        import journal_script
        from gogreen_core import Sculptor
        from gogreen_core.files.journal import Journal
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        data = journal_script.mesh()
        sculptor = Sculptor(data.vertices, data.faces)
        journal = Journal(sculptor, data, root={str(tmp_path / "child")!r}, auto_checkpoint=False)
        journal.flush()
        size = (journal.directory / "journal.jsonl").stat().st_size
        resource.setrlimit(resource.RLIMIT_FSIZE, (size + 4000, resource.RLIM_INFINITY))
        problems = []
        journal_script.run(sculptor, 3, lambda step: problems.extend(journal.take_problems()))
        journal.flush()
        print(journal.records, journal_script.fingerprint(sculptor))
        print(json.dumps(problems))
        journal.close(remove=False)
        """
    )
    result = subprocess.run(
        [sys.executable, "-c", child], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    records, final = result.stdout.splitlines()[0].split()
    problems = json.loads(result.stdout.splitlines()[1])
    assert len(problems) == 1 and "File too large" in problems[0], problems
    references = {}
    data = journal_script.mesh()
    sculptor = Sculptor(data.vertices, data.faces)
    journal = Journal(sculptor, data, root=tmp_path / "ref", auto_checkpoint=False)

    def after(_step: int) -> None:
        references[journal.records] = journal_script.fingerprint(sculptor)

    journal_script.run(sculptor, 3, after)
    journal.close()
    assert final == journal_script.fingerprint(sculptor)  # sculpting went on to the end
    (info,) = list_journals(tmp_path / "child")
    recovery = recover(info.directory)
    assert 0 < recovery.records == int(records) < max(references)
    assert journal_script.fingerprint(recovery.sculptor) == references[recovery.records]
    assert "was cut off" in recovery.notes[0]


def test_find_and_discard(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path)
    stroke(sculptor, 0)
    directory = crash(journal)
    assert find_journal(directory.name[:-2], tmp_path) == directory
    assert find_journal(str(directory), tmp_path) == directory
    with pytest.raises(JournalError, match="no journal 'nope'"):
        find_journal("nope", tmp_path)
    discard(directory)
    assert list_journals(tmp_path) == []


# -- gogreen recover ---------------------------------------------------------------------------
def test_gogreen_recover_lists_writes_and_discards(mesh, tmp_path, capsys):
    from app.cli import main
    from gogreen_core.mesh.mesh_io import load_mesh
    from gogreen_core.sculpt.session import load_session

    document = tmp_path / "model.obj"
    save_mesh(mesh, document)
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    journal = Journal(sculptor, mesh, document=str(document))  # the default place
    for k in range(3):
        stroke(sculptor, k)
    sculptor.undo()
    directory = crash(journal)
    running_sculptor, running = journaled(mesh, None)
    stroke(running_sculptor, 0)

    assert main(["recover", "--list"]) == 0
    out = capsys.readouterr().out
    assert directory.name in out and "model.obj" in out and str(document) in out
    assert "3 strokes, 1 undo" in out and "in use by a running GoGreen Sculpt" in out
    assert f"journals live in {recovery_root()}" in out

    output, session = tmp_path / "out.obj", tmp_path / "out.json"
    argv = ["recover", directory.name, "-o", str(output), "--session", str(session), "-q"]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "recovered model.obj: 4 operations" in err and "--discard` deletes it" in err
    assert np.array_equal(load_mesh(output).vertices, sculptor.vertices)
    replayed = Sculptor.from_session(load_session(session), mesh.vertices, mesh.faces)
    replayed.replay(load_session(session))
    assert np.array_equal(replayed.vertices, sculptor.vertices)

    assert main(["recover", running.directory.name, "-o", str(output)]) == 2
    assert "in use by a running GoGreen Sculpt" in capsys.readouterr().err
    assert main(["recover", "nope", "-o", str(output)]) == 2
    assert "no journal 'nope'" in capsys.readouterr().err
    assert main(["recover", directory.name, "--discard"]) == 0
    assert not directory.exists()
    running.close()
