"""The influence test of brush events (``_evaluation.near_segment``) decides as evaluation 1's did:
the vertices an old session's events reach must not change (sessions replay bit for bit)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit, prange

from gogreen_core._compiled import forced
from gogreen_core._evaluation import near_segment
from gogreen_core.brushes import mirror_signs


@njit(parallel=True, cache=True, fastmath={"contract"}, boundscheck=False, error_model="numpy")
def evaluation_1(points, start, step, radius, mirrors, origin, out):  # pragma: no cover
    """``near_segment`` as evaluation 1 had it (gogreen_core/_expansion.py at 9392a5d)."""
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    r2 = radius * radius
    for n in prange(points.shape[0]):
        hit = False
        for mi in range(mirrors.shape[0]):
            y0 = origin[0] + mirrors[mi, 0] * (points[n, 0] - origin[0]) - start[0]
            y1 = origin[1] + mirrors[mi, 1] * (points[n, 1] - origin[1]) - start[1]
            y2 = origin[2] + mirrors[mi, 2] * (points[n, 2] - origin[2]) - start[2]
            t = min(max((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
            d0 = y0 - t * step[0]
            d1 = y1 - t * step[1]
            d2 = y2 - t * step[2]
            hit = hit or d0 * d0 + d1 * d1 + d2 * d2 < r2
        out[n] = hit


@pytest.mark.parametrize("symmetry", ["", "x", "xz"])
def test_the_compiled_influence_test_decides_as_evaluation_1(symmetry):
    rng = np.random.default_rng(11)
    start, step = np.array([0.1, -0.2, 0.05]), np.array([0.3, 0.1, -0.2])
    radius, origin, signs = 0.7, np.array([0.05, 0.0, -0.1]), mirror_signs(symmetry)
    points = rng.normal(size=(200_000, 3)) * 0.6
    # points at rounding distance from the ball's surface: where contractions decide
    direction = rng.normal(size=(50_000, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    along = start + rng.random((50_000, 1)) * step
    points = np.vstack([points, along + radius * direction])
    expected = np.empty(len(points), dtype=bool)
    evaluation_1(points, start, step, radius, signs, origin, expected)
    got = np.empty(len(points), dtype=bool)
    with forced("generic"):
        near_segment(points, start, step, radius, signs, origin, got)
    assert np.array_equal(got, expected)
    assert 0.05 < expected.mean() < 0.95
    with forced("numpy"):  # the NumPy twin differs at most at rounding distance
        near_segment(points, start, step, radius, signs, origin, got)
    assert np.mean(got != expected) < 1e-3
