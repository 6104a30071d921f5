"""Undo history: bit-for-bit restores, redo, memory cap, input checks."""

from __future__ import annotations

import numpy as np
import pytest

from gogreen_core.sculpt.history import History


def bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def record_change(history: History, label: str, before, after, merge: bool = False) -> None:
    """Record the rows that differ between all positions ``before`` and ``after``."""
    history.record_rows(label, np.arange(len(before)), before, after, merge)


def entry_bytes(k: int) -> int:
    """Memory of one entry moving k vertices: int64 indices + two (k, 3) float64 blocks."""
    return 8 * k + 2 * 8 * 3 * k


def random_session(history: History, vertices: np.ndarray, steps: int, seed: int = 0):
    """Apply random edits (tiny and huge moves, -0.0, via both record methods); the states."""
    rng = np.random.default_rng(seed)
    states = [vertices.copy()]
    for k in range(steps):
        before = vertices.copy()
        idx = rng.choice(len(vertices), rng.integers(1, 60), replace=False)
        scale = 10.0 ** rng.integers(-12, 3)
        vertices[idx] += rng.normal(size=(len(idx), 3)) * scale
        vertices[idx[0]] = [-0.0, 1e-310, 3.0]
        if k % 2:
            record_change(history, f"edit {k}", before, vertices)
        else:
            history.record(f"edit {k}", idx, before[idx], vertices[idx])
        states.append(vertices.copy())
    return states


def test_undo_and_redo_restore_every_bit():
    vertices = np.random.default_rng(1).normal(size=(500, 3))
    history = History()
    states = random_session(history, vertices, steps=8)
    for k in range(8, 0, -1):
        assert history.undo(vertices) == f"edit {k - 1}"
        assert np.array_equal(bits(vertices), bits(states[k - 1]))
    assert history.undo(vertices) is None and not history.can_undo
    for k in range(1, 9):
        assert history.redo(vertices) == f"edit {k - 1}"
        assert np.array_equal(bits(vertices), bits(states[k]))
    assert history.redo(vertices) is None and not history.can_redo


def test_undo_and_redo_name_the_rows_they_wrote():
    """What a view redraws after an undo/redo: exactly the rows that changed (read-only)."""
    vertices = np.random.default_rng(2).normal(size=(300, 3))
    history = History()
    states = random_session(history, vertices, steps=3)
    for k, step in ((2, history.undo), (2, history.redo)):
        before = vertices.copy()
        step(vertices)
        written = history.restored_indices
        assert not written.flags.writeable
        assert np.array_equal(np.sort(written), np.flatnonzero(np.any(before != vertices, axis=1)))
        assert np.array_equal(vertices, states[k if step == history.undo else k + 1])


def test_record_change_compares_bits_and_stores_only_changed_rows():
    before = np.zeros((6, 3))
    after = before.copy()
    after[2, 0] = -0.0  # equal as a number, different bits: must be undoable exactly
    after[4] = [1.0, 2.0, 3.0]
    history = History()
    record_change(history, "move", before, after)
    assert history.memory_bytes == entry_bytes(2)
    history.undo(after)
    assert np.array_equal(bits(after), bits(before))
    nan = np.full((2, 3), np.nan)
    record_change(history, "nothing", nan, nan.copy())  # same NaN bits: no change
    assert history.undo_labels == []


def test_new_record_drops_redo_and_empty_change_does_not():
    vertices = np.zeros((4, 3))
    history = History()
    history.record("a", [0], [[0, 0, 0]], [[1, 0, 0]])
    vertices[0] = 1
    history.undo(vertices)
    assert history.can_redo and history.redo_labels == ["a"]
    record_change(history, "nothing", vertices, vertices.copy())
    history.record("empty", np.zeros(0, dtype=int), np.zeros((0, 3)), np.zeros((0, 3)))
    assert history.can_redo and history.undo_labels == []  # empty changes are not recorded
    history.record("b", [1], [[0, 0, 0]], [[0, 2, 0]])
    assert not history.can_redo and history.redo_labels == []
    assert history.undo_labels == ["b"]
    assert history.memory_bytes == entry_bytes(1)


def test_memory_cap_evicts_the_oldest_entries():
    size = entry_bytes(100)  # 5,600 bytes
    history = History(max_bytes=3 * size)
    for k in range(20):
        history.record(f"e{k}", np.arange(100), np.zeros((100, 3)), np.ones((100, 3)))
        assert history.memory_bytes <= 3 * size
    assert history.undo_labels == ["e17", "e18", "e19"]
    assert history.memory_bytes == 3 * size
    vertices = np.ones((100, 3))
    assert [history.undo(vertices) for _ in range(4)] == ["e19", "e18", "e17", None]
    assert history.memory_bytes == 3 * size  # undone entries still count (they can be redone)
    history.clear()
    assert history.memory_bytes == 0 and not history.can_undo and not history.can_redo


def test_an_entry_larger_than_the_cap_is_still_undoable():
    history = History(max_bytes=1000)
    history.record("small", [0], [[0, 0, 0]], [[1, 1, 1]])
    history.record("huge", np.arange(100), np.zeros((100, 3)), np.ones((100, 3)))
    assert history.undo_labels == ["huge"]
    assert history.memory_bytes == entry_bytes(100)


def test_recorded_arrays_are_copies():
    indices, before, after = np.array([1]), np.zeros((1, 3)), np.ones((1, 3))
    history = History()
    history.record("a", indices, before, after)
    indices[0], before[0, 0] = 0, 7.0
    vertices = np.ones((2, 3))
    history.undo(vertices)
    assert vertices.tolist() == [[1, 1, 1], [0, 0, 0]]


def test_bad_input_is_refused_without_changing_anything():
    with pytest.raises(ValueError, match="cap"):
        History(max_bytes=0)
    history = History()
    with pytest.raises(ValueError, match="shape"):
        history.record("a", [0, 1], np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="repeated"):
        history.record("a", [1, 1], np.zeros((2, 3)), np.ones((2, 3)))
    with pytest.raises(ValueError, match="negative"):
        history.record("a", [-1], np.zeros((1, 3)), np.ones((1, 3)))
    with pytest.raises(ValueError, match="shape"):
        record_change(history, "a", np.zeros((4, 3)), np.zeros((5, 3)))
    assert not history.can_undo and history.memory_bytes == 0

    history.record("move", [9], np.zeros((1, 3)), np.ones((1, 3)))
    with pytest.raises(ValueError, match="vertex 9"):
        history.undo(np.ones((5, 3)))  # not the array the entry came from
    with pytest.raises(TypeError, match="float64"):
        history.undo(np.ones((10, 3), dtype=np.float32))  # could not hold the exact values
    assert history.undo_labels == ["move"]  # still undoable
    vertices = np.ones((10, 3))
    assert history.undo(vertices) == "move" and vertices[9].tolist() == [0, 0, 0]


def test_merged_changes_undo_as_one_step_bit_for_bit():
    history = History()
    rng = np.random.default_rng(3)
    start = rng.normal(size=(50, 3))
    states = [start.copy()]
    for k in range(4):  # each step moves a different, overlapping set of rows
        nxt = states[-1].copy()
        nxt[k * 5 : k * 5 + 12] += rng.normal(size=(12, 3))
        record_change(history, "constraint drag", states[-1], nxt, merge=k > 0)
        states.append(nxt)
    assert history.undo_labels == ["constraint drag"]
    vertices = states[-1].copy()
    assert history.undo(vertices) == "constraint drag"
    assert np.array_equal(vertices, start)
    assert history.redo(vertices) == "constraint drag"
    assert np.array_equal(vertices, states[-1])
    # after an undo nothing merges into the undone entry
    history.undo(vertices)
    moved = vertices.copy()
    moved[0] += 1.0
    record_change(history, "constraint drag", vertices, moved, merge=True)
    assert history.undo_labels == ["constraint drag"] and not history.can_redo


def test_snapshot_and_restore_put_the_stacks_back():
    vertices = np.zeros((4, 3))
    history = History()
    history.record("a", [0], [[0.0, 0, 0]], [[1.0, 0, 0]])
    saved = history.snapshot()
    history.record("b", [1], [[0.0, 0, 0]], [[2.0, 0, 0]])
    history.undo(vertices)
    history.restore(saved)
    assert history.undo_labels == ["a"] and not history.can_redo
    assert history.memory_bytes == 8 + 2 * 24


def test_record_rows_of_candidates_keeps_what_all_rows_keep():
    """An operation that knows its rows records the same entry as a full comparison."""
    rng = np.random.default_rng(3)
    before = rng.normal(size=(200, 3))
    after = before.copy()
    after[[4, 50, 51]] += 1.0
    after[7] = -0.0 * before[7] + before[7]  # unchanged bits: left out
    full, rows = History(), History()
    record_change(full, "drag", before, after)
    candidates = np.array([4, 7, 50, 51, 120])
    rows.record_rows("drag", candidates, before[candidates], after[candidates])
    for history in (full, rows):
        vertices = after.copy()
        history.undo(vertices)
        assert np.array_equal(vertices, before)
        assert np.array_equal(history.restored_indices, [4, 50, 51])
