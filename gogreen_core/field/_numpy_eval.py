"""The evaluation in NumPy: no compilation, the reference the compiled code is held to (within
1e-12 relative: the float32 sums of the streamlines' upper degrees in the compiled order), serving
until the compiled code is ready (``_compiled``). Points go in chunks of CHUNK (bounded
temporaries); a point's result does not depend on its chunk.
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np

from gogreen_core.field._expansion import _HUGE, _TINY, BLOCK
from gogreen_core.field._integrator import (
    _SIXTH,
    _THIRD,
    CUTOFF_END,
    FIRST,
    MAX_ADAPTIVE_STEPS,
    PROBE,
    REFINE,
)
from gogreen_core.field._stream import StreamField

__all__ = ["expand", "segment_distance2", "stream_pass"]

#: Points evaluated at once (a few MB of temporaries).
CHUNK = 4096


def _geometry(offsets: np.ndarray, eps: float, power: int, n_seg: int) -> tuple[Any, ...]:
    """``_expansion._geometry`` for offsets (3, n): (x̂, ŷ, ẑ, r, loc, seg, scale0, scale1) and
    the single precision table variable σ = loc + 1 ∈ [0, 2] (as computed, not from loc)."""
    x, y, z = offsets
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        r2 = x * x + y * y + z * z
        r = np.sqrt(r2)
        huge = ~(r2 < 1e300)
        if huge.any():
            xs, ys, zs = x[huge] * _TINY, y[huge] * _TINY, z[huge] * _TINY
            r[huge] = np.sqrt(xs * xs + ys * ys + zs * zs) * _HUGE
        positive = r > 0.0
        inv = np.where(positive, 1.0 / r, 0.0)
        inv_re = 1.0 / (r + eps)
    u = np.minimum(r * inv_re, 1.0) * n_seg
    fj = np.fmin(np.floor(u), n_seg - 1.0)  # fmin: an overflowed stage's NaN ends NaN, refused
    scale = inv_re if power == 1 else inv_re * inv_re
    sigma = 2.0 * (u - fj)
    scale1 = np.where(positive, scale, 0.0)
    return x * inv, y * inv, z * inv, r, sigma - 1.0, fj.astype(np.int64), scale, scale1, sigma


def _radial(tables: np.ndarray, l_first: int, geometry: tuple[Any, ...]) -> list[np.ndarray]:
    """``_expansion._radial``: the radial term of each degree of the parity (n,)."""
    loc, seg, scale0, scale1 = geometry[4:8]
    s2 = loc * loc
    rows = []
    for d in range(tables.shape[0]):
        c = tables[d][seg]  # (n, 6): each point's segment
        p01 = c[:, 0] + c[:, 1] * loc
        p23 = c[:, 2] + c[:, 3] * loc
        p45 = c[:, 4] + c[:, 5] * loc
        rows.append((p01 + (p23 + p45 * s2) * s2) * (scale0 if d == 0 and l_first == 0 else scale1))
    return rows


def _angular(
    l_first: int,
    l_last: int,
    base: np.ndarray,
    coeffs: np.ndarray,
    beta: np.ndarray,
    geometry: tuple[Any, ...],
    rad: list[np.ndarray],
) -> np.ndarray:
    """``_expansion._angular`` for all points at once: (K, n)."""
    x, y, z = geometry[:3]
    # None until the first term is added (so typed Any, as are the sums of numpy operands)
    u: Any = None
    cos_m: Any = None
    sin_m: Any = None
    for m in range(l_last + 1):
        if m == 1:
            cos_m, sin_m = x, y
        elif m > 1:
            cos_m, sin_m = cos_m * x - sin_m * y, cos_m * y + sin_m * x
        part_a: Any = None
        part_b: Any = None
        prev: Any = None
        cur: Any = None
        for l in range(m, l_last + 1):
            if l == m + 1:
                prev, cur = np.ones_like(z), z
            elif l > m + 1:
                prev, cur = cur, z * cur - beta[l, m] * prev
            if (l - l_first) % 2 != 0 or l < l_first:
                continue
            row = rad[(l - l_first) // 2]
            t = row if l == m else row * cur
            ca = coeffs[base[l] + l + m][:, None]
            cs = coeffs[base[l] + l - m][:, None]
            if part_a is None:
                part_a = t * ca
                part_b = t * cs if m > 0 else None
            else:
                part_a = part_a + t * ca
                if m > 0:
                    part_b = part_b + t * cs
        u = part_a if m == 0 else (u + cos_m * part_a) + sin_m * part_b
    return cast(np.ndarray, u)


def expand(
    points: np.ndarray,
    center: np.ndarray,
    eps: float,
    power: int,
    l_first: int,
    l_last: int,
    base: np.ndarray,
    coeffs: np.ndarray,
    beta: np.ndarray,
    tables: np.ndarray,
) -> np.ndarray:
    """``_expansion.expand_blocks`` over all ``points`` (N, 3) → (N, K)."""
    out = np.empty((points.shape[0], coeffs.shape[1]))
    for start in range(0, points.shape[0], CHUNK):
        part = points[start : start + CHUNK]
        offsets = np.stack([part[:, k] - center[k] for k in range(3)])
        geometry = _geometry(offsets, eps, power, tables.shape[1])
        rad = _radial(tables, l_first, geometry)
        out[start : start + CHUNK] = _angular(l_first, l_last, base, coeffs, beta, geometry, rad).T
    return out


def _single_field(field: StreamField, geometry: tuple[Any, ...]) -> np.ndarray:
    """``_integrator._single_velocity``'s field before the weight (K, n): the parity's lowest
    degree in float64 plus the degrees above it in float32."""
    l_first, l_last, base, coeffs = field.l_first, field.l_last, field.base, field.coeffs
    coeffs32, beta32, tables32, cscale = field.coeffs32, field.beta32, field.tables32, field.cscale
    x, y, z = geometry[:3]
    t = _radial(field.tables, l_first, geometry)[0]
    c0, c1, c2 = (coeffs[j][:, None] for j in ((0, 1, 2) if l_first else (0, 0, 0)))
    low = t * c0 if l_first == 0 else ((t * z) * c1 + x * (t * c2)) + y * (t * c0)
    if l_last > l_first:
        single = tuple(v.astype(np.float32) for v in geometry[:3])
        loc, seg = geometry[8].astype(np.float32), geometry[5]
        c, s = tables32[seg], loc[:, None]  # (n, n_deg, 3): each point's segment
        rad = list((c[..., 0] + (c[..., 1] + c[..., 2] * s) * s).T)
        total = _angular(l_first + 2, l_last, base, coeffs32, beta32, single, rad)
    else:
        total = np.zeros((3, len(x)), dtype=np.float32)
    return cast(np.ndarray, low + (geometry[7] * cscale) * total)


def _velocity(pos: np.ndarray, t: float, field: StreamField) -> np.ndarray:
    """``_integrator._single_velocity`` at positions (3, n) → (3, n)."""
    vel: Any = None
    for mi, signs in enumerate(field.mirrors):
        c = field.center0 + t * field.center_step
        o = field.origin[:, None]
        image = np.where(signs[:, None] > 0, pos, o - (pos - o))
        geometry = _geometry(image - c[:, None], field.eps, field.power, field.tables.shape[1])
        u = np.clip((geometry[3] - field.cutoff_inner) * field.inv_width, 0.0, 1.0)
        weight = np.where(u < CUTOFF_END, 1.0 - u * u * u * (10.0 + u * (6.0 * u - 15.0)), 0.0)
        term = np.where(
            weight != 0.0, (signs[:, None] * weight) * _single_field(field, geometry), 0.0
        )
        vel = term if mi == 0 else vel + term
    return cast(np.ndarray, vel)


def _rk4(
    n_steps: int, start: np.ndarray, field: StreamField, want_mid: bool
) -> tuple[np.ndarray, Any]:
    """``_integrator._steps`` (RK4) from start (3, n) → (end, mid (6, n) or None)."""
    h = 1.0 / n_steps
    pos = start
    mid: Any = np.empty((6, start.shape[1])) if want_mid else None
    end: Any = None
    for step in range(n_steps):
        t0 = step * h
        vel: Any = None
        for stage in range(4):
            a = 0.0 if stage == 0 else (h if stage == 3 else 0.5 * h)
            vel = _velocity(pos if stage == 0 else pos + a * vel, t0 + a, field)
            if want_mid and n_steps == 1:
                if stage == 0:
                    mid[3:] = pos + 0.5 * vel
                elif stage == 1:
                    mid[:3] = pos + vel
                elif stage == 3:
                    mid[3:] = mid[3:] + 0.5 * vel
            weight = h / 6.0 if stage == 0 or stage == 3 else h / 3.0
            end = (pos if stage == 0 else end) + weight * vel
        pos = end
    return end, mid


def _rk3(start: np.ndarray, field: StreamField) -> tuple[np.ndarray, np.ndarray]:
    """``_integrator._steps`` (third order) from start (3, n) → (end, squared spread (n,))."""
    k1 = _velocity(start, 0.0, field)
    ksum = k1 + _velocity(start + k1, 1.0, field)
    k3 = _velocity(start + 0.25 * ksum, 0.5, field)
    end = start + (ksum + 4.0 * k3) * _SIXTH
    d = (2.0 * k3 - ksum) * _THIRD
    return end, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]


def _norm2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d0, d1, d2 = a[0] - b[0], a[1] - b[1], a[2] - b[2]
    return cast(np.ndarray, d0 * d0 + d1 * d1 + d2 * d2)


def stream_pass(
    kind: int, points: np.ndarray, indices: np.ndarray, indexed: bool, in_place: bool,
    limit: float, field: StreamField, n_steps: int, adaptive: bool, third_order: bool,
    level: float, picked_rows: np.ndarray, out: np.ndarray, evaluations: np.ndarray,
    found: np.ndarray, block_found: np.ndarray, problem: np.ndarray, bad: np.ndarray,
    first_block: int, last_block: int,
) -> None:  # fmt: skip
    """``_integrator._pass`` (the same arguments but ``in_place``), CHUNK points at a time."""
    n_points = indices.shape[0] if indexed else points.shape[0]
    n_points = n_points if kind == FIRST else picked_rows.shape[0]
    last = min(last_block * BLOCK, n_points)
    for first in range(first_block * BLOCK, last, CHUNK):
        span = np.arange(first, min(first + CHUNK, last))
        with np.errstate(all="ignore"):  # overflows are reported (status 3), as compiled
            blocks = span // BLOCK
            first_of = np.flatnonzero(np.r_[True, blocks[1:] != blocks[:-1]])  # blocks' starts
            if kind == REFINE:
                picked = picked_rows[span]
                previous = out[picked].T
                changes = np.zeros(len(picked))
                steps = 2
                while picked.size:
                    rows = indices[picked] if indexed else picked
                    start = np.ascontiguousarray(points[rows].T)
                    end, _ = _rk4(steps, start, field, False)
                    out[picked] = end.T
                    if len(evaluations):
                        evaluations[picked] += 4 * steps
                    change = np.sqrt(_norm2(end, previous))
                    again = (change > 15.0 * level) | (changes > 240.0 * level)
                    again &= steps < MAX_ADAPTIVE_STEPS
                    bad[blocks[~again][~np.isfinite(end[:, ~again]).all(axis=0)]] = True
                    picked, previous, blocks = picked[again], end[:, again], blocks[again]
                    changes = change[again]
                    steps *= 2
                continue
            rows = span if kind == FIRST else picked_rows[span]
            if indexed:
                rows = indices[rows]
                outside = (rows < 0) | (rows >= points.shape[0])
                rows = np.where(outside, 0, rows)
            start = np.ascontiguousarray(points[rows].T)
            if indexed:
                outside = np.maximum.reduceat(outside, first_of)
                wrong = np.maximum.reduceat(~(np.abs(start) <= limit).all(axis=0), first_of)
                if kind == PROBE:  # the first pass reports them
                    keep = ~np.isin(blocks, blocks[first_of][outside | wrong])
                    found[0, span[~keep]] = np.inf
                    span, start = span[keep], start[:, keep]
                else:
                    problem[blocks[first_of][wrong]] = 2
                    problem[blocks[first_of][outside]] = 1
            if kind == PROBE:
                third, spread = _rk3(start, field)
                coarse, _ = _rk4(1, start, field, False)
                fourth, _ = _rk4(2, start, field, False)
                richardson = np.sqrt(_norm2(fourth, coarse)) / 15.0
                error = np.sqrt(_norm2(third, fourth)) + richardson
                found[:, span] = (error, spread, _norm2(fourth, start))
                continue
            if third_order:
                end, spread = _rk3(start, field)
            else:
                end, mid = _rk4(n_steps, start, field, adaptive)
            out[span] = end.T
            if len(evaluations):  # (an empty array: not counted)
                evaluations[span] = 3 if third_order else 4 * n_steps
            overflow = np.logical_or.reduceat(~np.isfinite(end).all(axis=0), first_of)
            bad[blocks[first_of][overflow]] = True
            if not adaptive:
                continue
            m2 = _norm2(end, start)
            if third_order:
                rank = np.where(spread <= level, 0.0, np.inf)
            else:
                e = np.sqrt(np.maximum(_norm2(mid[:3], end), _norm2(mid[3:], end)))
                reach2 = np.maximum(m2, e * e)
                rank = np.where(reach2 > 0.0, e * e * e * e * e / reach2, 0.0)
            found[0, span] = rank
            block_found[0, blocks[first_of]] = np.sqrt(np.maximum.reduceat(m2, first_of))
            block_found[1, blocks[first_of]] = np.maximum.reduceat(rank, first_of)


def segment_distance2(
    points: np.ndarray, start: np.ndarray, step: np.ndarray, mirrors: np.ndarray, origin: np.ndarray
) -> np.ndarray:
    """(N,) the squared distance of the nearest mirror image of each of ``points`` (N, 3)
    (``mirrors`` (m, 3) signs about ``origin``) to the segment ``start`` → ``start + step``."""
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    y = origin + mirrors[:, None] * (points - origin) - start  # (m, N, 3) images
    along = y[..., 0] * step[0] + y[..., 1] * step[1] + y[..., 2] * step[2]
    t = np.clip(along * (1.0 / length2 if length2 > 0.0 else 0.0), 0.0, 1.0)
    return cast(np.ndarray, np.square(y - t[..., None] * step).sum(axis=2).min(axis=0))
