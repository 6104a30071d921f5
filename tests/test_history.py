"""Undo history: bit-for-bit restores, redo, memory cap."""

import numpy as np
import pytest

from gogreen_core.history import History


def test_undo_redo_are_bit_exact():
    rng = np.random.default_rng(0)
    vertices = rng.normal(size=(500, 3))
    history = History()
    states = [vertices.copy()]
    for k in range(5):
        before = vertices.copy()
        idx = rng.choice(500, 40, replace=False)
        vertices[idx] += rng.normal(size=(40, 3)) * 1e-7
        history.record_change(f"edit {k}", before, vertices)
        states.append(vertices.copy())
    for k in range(5, 0, -1):
        assert history.undo(vertices) == f"edit {k - 1}"
        assert np.array_equal(vertices, states[k - 1])
    assert history.undo(vertices) is None
    for k in range(1, 6):
        history.redo(vertices)
        assert np.array_equal(vertices, states[k])


def test_new_record_clears_redo_and_empty_change_is_ignored():
    vertices = np.zeros((4, 3))
    history = History()
    history.record("a", [0], [[0, 0, 0]], [[1, 0, 0]])
    vertices[0] = 1
    history.undo(vertices)
    assert history.can_redo
    history.record("b", [1], [[0, 0, 0]], [[0, 2, 0]])
    assert not history.can_redo
    history.record_change("nothing", vertices, vertices.copy())
    assert history.undo_labels == ["b"]


def test_memory_cap_drops_oldest():
    history = History(max_bytes=10_000)
    for k in range(20):
        idx = np.arange(100)
        history.record(f"e{k}", idx, np.zeros((100, 3)), np.ones((100, 3)))
    assert history.memory_bytes <= 10_000
    assert history.undo_labels[-1] == "e19" and "e0" not in history.undo_labels
    with pytest.raises(ValueError, match="cap"):
        History(max_bytes=0)
