"""The compiled loops of :mod:`gogreen_core.mesh.influence` (serial, GIL released, run over
ranges of blocks by ``_parallel``; compiled with the drivers). Blocks are the runs of
:data:`BLOCK` consecutive vertex rows; a block's box is the exact minimum and maximum (3,) of
its rows. The constants live here: numba's disk cache is keyed on this file.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

if TYPE_CHECKING:
    from gogreen_core._jit_options import NogilJitOptions

#: Rows per block: log2 and count (64 rows: tight boxes, 15.5k boxes for 1M vertices).
BLOCK_SHIFT = 6
BLOCK = 1 << BLOCK_SHIFT
#: The box tests' margin, relative to the largest coordinate, radius or step in play.
SLACK = 2.0**-36
#: Largest coordinate, radius or step the box tests take (their squares stay finite).
MAX_SCALE = 1e150
#: A block's status: out of every capsule, inside one (taken whole), or its rows to test.
OUT, INSIDE, TESTED = 0, 1, 2

_JIT: NogilJitOptions = {"cache": True, "boundscheck": False, "error_model": "numpy", "nogil": True}


@njit(cache=True, boundscheck=False, nogil=True, error_model="numpy", fastmath={"contract"})
def near_segment_rows(
    points: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
    out: NDArray[np.bool_],
    first: int,
    last: int,
) -> None:
    """out[n] for n in [first, last): some mirror image of points[n] is within ``radius`` of the
    segment start → start + step. The one per-point influence test (over every row, and over
    the blocks a capsule meets: both give the same rows)."""
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    r2 = radius * radius
    for mi in range(mirrors.shape[0]):
        m0, m1, m2 = mirrors[mi, 0], mirrors[mi, 1], mirrors[mi, 2]
        for n in range(first, last):
            y0 = origin[0] + m0 * (points[n, 0] - origin[0]) - start[0]
            y1 = origin[1] + m1 * (points[n, 1] - origin[1]) - start[1]
            y2 = origin[2] + m2 * (points[n, 2] - origin[2]) - start[2]
            t = min(max((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
            d0 = y0 - t * step[0]
            d1 = y1 - t * step[1]
            d2 = y2 - t * step[2]
            near = d0 * d0 + d1 * d1 + d2 * d2 < r2
            out[n] = near if mi == 0 else (out[n] or near)


@njit(**_JIT)
def _mark(rows: NDArray[np.int64], n: int, dirty: NDArray[np.bool_]) -> None:
    """dirty[b] for the block of every row of ``rows`` (numpy's indexing: negative rows count
    from the end; rows out of range are no rows)."""
    low, high = n, -1
    for i in range(rows.shape[0]):  # vectorized: then the common case's loop has no branch
        low = min(low, rows[i])
        high = max(high, rows[i])
    if 0 <= low and high < n:
        for i in range(rows.shape[0]):
            dirty[rows[i] >> BLOCK_SHIFT] = True
        return
    for i in range(rows.shape[0]):
        r = rows[i]
        if r < 0:
            r += n
        if 0 <= r < n:
            dirty[r >> BLOCK_SHIFT] = True


@njit(**_JIT)
def _refit(
    vertices: NDArray[np.float64],
    blocks: NDArray[np.int64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    first: int,
    last: int,
) -> None:
    """lo[b], hi[b] = the exact minimum and maximum (3,) of the rows of block b, for the blocks
    ``blocks[first:last]`` (NaN coordinates are left out; a block of NaN rows gets lo > hi)."""
    n = vertices.shape[0]
    for j in range(first, last):
        b = blocks[j]
        begin = b << BLOCK_SHIFT
        end = min(begin + BLOCK, n)
        lo0 = lo1 = lo2 = np.inf
        hi0 = hi1 = hi2 = -np.inf
        for i in range(begin, end):  # min(a, x) is a unless x < a: NaN is left out
            x, y, z = vertices[i, 0], vertices[i, 1], vertices[i, 2]
            lo0, lo1, lo2 = min(lo0, x), min(lo1, y), min(lo2, z)
            hi0, hi1, hi2 = max(hi0, x), max(hi1, y), max(hi2, z)
        lo[b, 0], lo[b, 1], lo[b, 2] = lo0, lo1, lo2
        hi[b, 0], hi[b, 1], hi[b, 2] = hi0, hi1, hi2


@njit(**_JIT)
def _classify(
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    n_rows: int,
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
    status: NDArray[np.uint8],
    images: NDArray[np.uint8],
    hits: NDArray[np.int64],
) -> tuple[int, int]:
    """Each block's status (OUT, INSIDE a capsule, TESTED) and images (bit i: the capsule of
    mirror image i may meet its box); ``hits`` gets the blocks not OUT in order. Returns
    (their count, the rows TESTED), or (-1, 0) past :data:`MAX_SCALE`."""
    n_blocks, n_images = lo.shape[0], mirrors.shape[0]
    r = abs(radius)
    scale = r
    for k in range(3):
        scale = max(scale, abs(origin[k]), abs(start[k]), abs(step[k]), abs(start[k] + step[k]))
    for b in range(n_blocks):
        if lo[b, 0] <= hi[b, 0]:
            for k in range(3):
                scale = max(scale, abs(lo[b, k]), abs(hi[b, k]))
    if not scale <= MAX_SCALE:
        return -1, 0
    slack = SLACK * scale
    inner = r - slack
    inner2 = inner * inner if inner > 0.0 else -1.0
    # per image: the segment's start a and step d, 1/|d|², its box grown by the radius, its
    # midpoint and the radius of the ball around it holding the capsule
    a = np.empty((n_images, 3))
    d = np.empty((n_images, 3))
    qlo = np.empty((n_images, 3))
    qhi = np.empty((n_images, 3))
    mid = np.empty((n_images, 3))
    inv = np.empty(n_images)
    ball2 = np.empty(n_images)
    for mi in range(n_images):
        length2 = 0.0
        for k in range(3):
            a[mi, k] = origin[k] + mirrors[mi, k] * (start[k] - origin[k])
            d[mi, k] = mirrors[mi, k] * step[k]
            length2 += d[mi, k] * d[mi, k]
            qlo[mi, k] = min(a[mi, k], a[mi, k] + d[mi, k]) - (r + slack)
            qhi[mi, k] = max(a[mi, k], a[mi, k] + d[mi, k]) + (r + slack)
            mid[mi, k] = a[mi, k] + 0.5 * d[mi, k]
        inv[mi] = 1.0 / length2 if length2 > 0.0 else 0.0
        ball = r + 0.5 * np.sqrt(length2) + slack
        ball2[mi] = ball * ball
    n_hits = 0
    partial_rows = 0
    for b in range(n_blocks):
        state, bits = 0, 0
        if lo[b, 0] <= hi[b, 0]:
            for mi in range(n_images):
                out = False
                for k in range(3):
                    out = out or hi[b, k] < qlo[mi, k] or lo[b, k] > qhi[mi, k]
                if out:
                    continue
                gap2 = 0.0
                for k in range(3):
                    e = min(max(mid[mi, k], lo[b, k]), hi[b, k]) - mid[mi, k]
                    gap2 += e * e
                if gap2 > ball2[mi]:
                    continue
                bits |= 1 << mi
                if state == INSIDE or inner2 < 0.0:
                    continue
                # inside the ball of radius r about the segment's start (within the capsule)?
                far2 = 0.0
                for k in range(3):
                    far = max(abs(lo[b, k] - a[mi, k]), abs(hi[b, k] - a[mi, k]))
                    far2 += far * far
                if far2 < inner2:
                    state = INSIDE
                    continue
                # inside the (convex) capsule iff its 8 corners are
                inside = True
                for corner in range(8):
                    y0 = (hi[b, 0] if corner & 1 else lo[b, 0]) - a[mi, 0]
                    y1 = (hi[b, 1] if corner & 2 else lo[b, 1]) - a[mi, 1]
                    y2 = (hi[b, 2] if corner & 4 else lo[b, 2]) - a[mi, 2]
                    t = (y0 * d[mi, 0] + y1 * d[mi, 1] + y2 * d[mi, 2]) * inv[mi]
                    t = min(max(t, 0.0), 1.0)
                    e0, e1, e2 = y0 - t * d[mi, 0], y1 - t * d[mi, 1], y2 - t * d[mi, 2]
                    if not e0 * e0 + e1 * e1 + e2 * e2 < inner2:
                        inside = False
                        break
                if inside:
                    state = INSIDE
        if bits:
            if state != INSIDE:
                state = TESTED
                begin = b << BLOCK_SHIFT
                partial_rows += min(begin + BLOCK, n_rows) - begin
            hits[n_hits] = b
            n_hits += 1
        status[b] = state
        images[b] = bits
    return n_hits, partial_rows


@njit(**_JIT)
def _test_blocks(
    points: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
    hits: NDArray[np.int64],
    status: NDArray[np.uint8],
    images: NDArray[np.uint8],
    near: NDArray[np.bool_],
    counts: NDArray[np.int64],
    first: int,
    last: int,
) -> None:
    """For the blocks ``hits[first:last]``: near[rows] by the per-point test with the images
    that may reach the block (blocks to test), and counts[j] the rows reached."""
    n = points.shape[0]
    chosen = np.empty_like(mirrors)
    for j in range(first, last):
        b = hits[j]
        begin = b << BLOCK_SHIFT
        end = min(begin + BLOCK, n)
        if status[b] == INSIDE:
            counts[j] = end - begin
            continue
        k = 0
        for mi in range(mirrors.shape[0]):
            if (images[b] >> mi) & 1:
                chosen[k] = mirrors[mi]
                k += 1
        near_segment_rows(points, start, step, radius, chosen[:k], origin, near, begin, end)
        c = 0
        for i in range(begin, end):
            c += near[i]
        counts[j] = c


@njit(**_JIT)
def _emit(
    n: int,
    hits: NDArray[np.int64],
    status: NDArray[np.uint8],
    near: NDArray[np.bool_],
    offsets: NDArray[np.int64],
    out: NDArray[np.int64],
    first: int,
    last: int,
) -> None:
    """The reached rows of the blocks ``hits[first:last]``, in order, from out[offsets[j]]."""
    for j in range(first, last):
        b = hits[j]
        begin = b << BLOCK_SHIFT
        end = min(begin + BLOCK, n)
        o = offsets[j]
        if status[b] == INSIDE:
            for i in range(begin, end):
                out[o] = i
                o += 1
        else:
            for i in range(begin, end):
                if near[i]:
                    out[o] = i
                    o += 1


def compile_calls() -> list[tuple[Any, tuple[Any, ...]]]:
    """(dispatcher, arguments) of every compiled function here, typed as called, empty ranges."""
    f3, f33, rows = np.zeros(3), np.zeros((1, 3)), np.zeros(1, dtype=np.int64)
    flags, small = np.zeros(1, dtype=np.bool_), np.zeros(1, dtype=np.uint8)
    return [
        (near_segment_rows, (f33, f3, f3, 1.0, f33, f3, flags, 0, 0)),
        (_mark, (rows, 0, flags)),
        (_refit, (f33, rows, f33, f33, 0, 0)),
        (_classify, (np.zeros((0, 3)), np.zeros((0, 3)), 0, f3, f3, 1.0, f33, f3, small, small,
                     rows)),
        (_test_blocks, (f33, f3, f3, 1.0, f33, f3, rows, small, small, flags, rows, 0, 0)),
        (_emit, (0, rows, small, flags, rows, rows, 0, 0)),
    ]  # fmt: skip
