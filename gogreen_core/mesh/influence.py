"""Which vertices a brush event can reach, without a pass over every vertex.

An event reaches the vertices p some mirror image o + M (p - o) of which lies within ``radius``
of the segment ``start`` → ``start + step`` (``_evaluation.near_segment``, the influence test;
it must not change for old sessions). Over every vertex of a 1M-vertex mesh that costs 5-9 ms.

:class:`VertexBlocks` keeps the bounding box of every block of :data:`BLOCK` consecutive rows
(mesh files list vertices with locality: on the twice-subdivided ogre half the blocks span under
1.3 % of the model). A query tests the boxes against its capsules (the segment dilated by the
radius, one per mirror image): a block out of every capsule is skipped, one inside a capsule is
taken whole, the rows of the others get the plain pass's own compiled per-point test. The rows
come out ascending and equal to the plain pass's bit for bit: the box tests are conservative by
``SLACK`` (2⁻³⁶) times the largest coordinate, radius or step in play, a thousand times the
per-point test's rounding. Inputs where that argument fails (values near the float range's ends,
signs other than ±1, more than 8 images), queries where most rows need the test, arrays without
locality (:data:`DORMANT_EXTENT`) and a machine whose compiled code is not ready yet go to the
plain pass. Writes report their rows (:meth:`VertexBlocks.changed`, through ``MeshState``); the
next query refits those boxes. :data:`VERIFY` checks every answer (the tests turn it on).
"""

from __future__ import annotations

import threading
import weakref
from functools import partial

import numpy as np
from numpy.typing import NDArray

from gogreen_core import _compiled
from gogreen_core._parallel import run_ranges
from gogreen_core.field import _evaluation
from gogreen_core.field._influence_compiled import (
    BLOCK,
    BLOCK_SHIFT,
    MAX_SCALE,
    _classify,
    _emit,
    _mark,
    _refit,
    _test_blocks,
)

__all__ = ["BLOCK", "VERIFY", "VertexBlocks", "plain_rows_near"]

#: The range of squared step lengths where the test's 1 / |step|² is finite and accurate.
STEP2_RANGE = (1e-250, 1e250)
#: Most mirror images (one bit each in a block's mask).
MAX_IMAGES = 8
#: Above this fraction of the rows needing the per-point test, the plain pass serves.
PLAIN_FRACTION = 0.5
#: An array whose median block spans more than this fraction of its bounding box's diagonal
#: (no locality) is left to the plain pass: the blocks would save nothing.
DORMANT_EXTENT = 0.25
#: Check every answer against the plain pass (recorded in :data:`mismatches`, raised); the
#: blocks then answer for every vertex order, so the tests check them on every mesh.
VERIFY = False
#: What :data:`VERIFY` found (descriptions), for a test harness to assert empty.
mismatches: list[str] = []
#: Fewest blocks a thread of the pool takes at once (each block 64 rows).
MIN_BLOCKS = 256

#: (start (3,), step (3,), radius, mirrors (k, 3), origin (3,)): what a query asks.
Query = tuple[
    NDArray[np.float64], NDArray[np.float64], float, NDArray[np.float64], NDArray[np.float64]
]


def plain_rows_near(
    points: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
    compiled: bool,
) -> NDArray[np.int64]:
    """The rows (n,) int64 of ``points`` (N, 3) the influence test keeps, by a pass over all of
    them (``_evaluation.near_segment``, NumPy's unless ``compiled``) and ``np.flatnonzero``."""
    out = np.empty(len(points), dtype=np.bool_)
    _evaluation.near_segment(points, start, step, radius, mirrors, origin, out, compiled)
    return np.flatnonzero(out)


class VertexBlocks:
    """The influence test of one vertex array, answered with the bounding boxes of its blocks
    of :data:`BLOCK` consecutive rows (see the module docstring): lo, hi (n_blocks, 3) (lo > hi:
    no finite row), dirty (n_blocks,) (written since fitted). One lock guards them, so a
    background query and another thread's writes may interleave."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        #: Answers given by the blocks and by the plain pass (what a benchmark reports).
        self.answers = {"blocks": 0, "plain": 0}
        self._index(np.empty((0, 3)))  # an array freed at once: no array is served yet

    def _serves(self, vertices: NDArray[np.float64]) -> bool:
        return self._array() is vertices and len(vertices) == self._n

    def _index(self, vertices: NDArray[np.float64]) -> None:
        """Serve ``vertices`` from now on: every box to be fitted (at the next query)."""
        self._array: weakref.ref[NDArray[np.float64]] = weakref.ref(vertices)
        self._n = n = len(vertices)
        n_blocks = -(-n // BLOCK)
        self._lo, self._hi = np.empty((n_blocks, 3)), np.empty((n_blocks, 3))
        self._dirty = np.ones(n_blocks, dtype=np.bool_)
        self._near = np.empty(n, dtype=np.bool_)
        self._dormant: bool | None = None  # decided with the first boxes
        self._answer: tuple[NDArray[np.int64], ...] = ()  # the last answer, its blocks not OUT

    def changed(self, vertices: NDArray[np.float64], rows: NDArray[np.integer] | None) -> None:
        """Rows ``rows`` (k,) of ``vertices`` (N, 3) were written (None: any row may have been):
        their boxes are refitted before the next answer. Nothing to do for another array."""
        compiled = _compiled.drivers()
        with self._lock:
            if not self._serves(vertices) or self._dormant:
                return
            if rows is None:
                self._dirty[:] = True
                return
            if self._answer and rows is self._answer[0]:  # an answer (unchanged): no row pass
                self._dirty[self._answer[1]] = True
                return
            rows = np.ascontiguousarray(rows, dtype=np.int64).ravel()
            if compiled:
                _mark(rows, self._n, self._dirty)
            else:  # as ``_mark``: negative rows count from the end, others out of range none
                rows = rows[(rows >= -self._n) & (rows < self._n)] % max(self._n, 1)
                self._dirty[rows >> BLOCK_SHIFT] = True

    def rows_near(
        self,
        vertices: NDArray[np.float64],
        start: NDArray[np.float64],
        step: NDArray[np.float64],
        radius: float,
        mirrors: NDArray[np.float64],
        origin: NDArray[np.float64],
    ) -> NDArray[np.int64]:
        """The rows (n,) int64, ascending, of ``vertices`` (N, 3) the influence test keeps
        (module docstring; ``mirrors`` (k, 3) ±1 signs about ``origin`` (3,)): exactly
        :func:`plain_rows_near`'s."""
        query: Query = (
            np.ascontiguousarray(start, dtype=np.float64),
            np.ascontiguousarray(step, dtype=np.float64),
            float(radius),
            np.ascontiguousarray(mirrors, dtype=np.float64),
            np.ascontiguousarray(origin, dtype=np.float64),
        )
        compiled = _compiled.drivers()
        with self._lock:
            rows = None
            if not self._serves(vertices):
                self._index(vertices)
            if compiled and _usable(*query[:4]) and not self._dormant:
                self._refit(vertices)
                if self._dormant is None:
                    self._dormant = not VERIFY and self._without_locality()
                if not self._dormant:
                    rows = self._by_blocks(vertices, query)
            self.answers["plain" if rows is None else "blocks"] += 1
            # (other threads may see the GUI thread's writes mid-way: the main thread checks)
            main = threading.current_thread() is threading.main_thread()
            if rows is not None and VERIFY and main:
                _verify(rows, plain_rows_near(vertices, *query, compiled))
        return plain_rows_near(vertices, *query, compiled) if rows is None else rows

    def _refit(self, vertices: NDArray[np.float64]) -> None:
        """Fit the boxes of the blocks written since they were fitted."""
        dirty = np.flatnonzero(self._dirty)
        if len(dirty):
            run_ranges(partial(_refit, vertices, dirty, self._lo, self._hi), len(dirty), MIN_BLOCKS)
            self._dirty[dirty] = False

    def _without_locality(self) -> bool:
        """Whether the median block spans over :data:`DORMANT_EXTENT` of the bbox diagonal."""
        lo, hi = self._lo, self._hi
        valid = np.all(lo <= hi, axis=1)
        if not valid.any():
            return True
        lo, hi = lo[valid], hi[valid]
        diagonal = float(np.linalg.norm(hi.max(axis=0) - lo.min(axis=0)))
        return bool(np.median((hi - lo).max(axis=1)) > DORMANT_EXTENT * diagonal)

    def _by_blocks(self, vertices: NDArray[np.float64], query: Query) -> NDArray[np.int64] | None:
        """The answer by the blocks (compiled loops), or None for the plain pass."""
        n, n_blocks = len(vertices), len(self._lo)
        status = np.empty(n_blocks, dtype=np.uint8)
        images = np.empty(n_blocks, dtype=np.uint8)
        hits = np.empty(n_blocks, dtype=np.int64)
        n_hits, tested_rows = _classify(self._lo, self._hi, n, *query, status, images, hits)
        if n_hits < 0 or tested_rows > PLAIN_FRACTION * n:
            return None
        hits = hits[:n_hits]
        counts = np.empty(n_hits, dtype=np.int64)
        near = self._near
        test = partial(_test_blocks, vertices, *query, hits, status, images, near, counts)
        run_ranges(test, n_hits, MIN_BLOCKS)
        ends = np.cumsum(counts)
        out = np.empty(int(ends[-1]) if n_hits else 0, dtype=np.int64)
        run_ranges(partial(_emit, n, hits, status, near, ends - counts, out), n_hits, MIN_BLOCKS)
        self._answer = (out, hits)
        return out


def _verify(rows: NDArray[np.int64], plain: NDArray[np.int64]) -> None:
    """Record and raise a difference between the blocks' answer and the plain pass's."""
    if not np.array_equal(rows, plain):
        missing, extra = np.setdiff1d(plain, rows)[:5], np.setdiff1d(rows, plain)[:5]
        mismatches.append(
            f"{len(rows)} rows by the blocks, {len(plain)} by the plain pass; missing "
            f"{missing.tolist()}, extra {extra.tolist()}"
        )
        raise AssertionError(f"stale vertex blocks: {mismatches[-1]}")


def _usable(
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
) -> bool:
    """Whether the blocks may answer (module docstring; the boxes check the coordinates)."""
    if not (start.shape == step.shape == (3,) and mirrors.ndim == 2 and mirrors.shape[1] == 3):
        return False
    if not (1 <= len(mirrors) <= MAX_IMAGES and np.all(np.abs(mirrors) == 1.0)):
        return False
    r = abs(radius)
    with np.errstate(over="ignore", under="ignore"):
        length2 = float(step[0] * step[0] + step[1] * step[1] + step[2] * step[2])
    return (r == 0.0 or 1e-150 <= r <= MAX_SCALE) and (  # NaN fails both
        length2 == 0.0 or STEP2_RANGE[0] <= length2 <= STEP2_RANGE[1]
    )
