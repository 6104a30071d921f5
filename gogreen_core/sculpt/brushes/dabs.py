"""The detail brushes' common step: dabs along the swept segment, as Blender's sculpt brushes.

The detail brushes (draw, clay_strips, crease, flatten, inflate) act in *dabs* spaced
:data:`DAB_SPACING` of their radius ``R`` along the stroke (carried between events: Blender's
"space" stroke), so how much a stroke raises does not depend on the mouse's speed or rate; a
member's rate ``r`` per radius of stroke is ``r · DAB_SPACING`` per dab.

Each dab sees the surface the previous dabs left: the vertices within ``R`` (2 ε automatic)
weighted by ``f`` = 1 − smoothstep(d / R), their f-weighted mean normal ``N`` and position ``C``
(Blender's ``calc_area_normal_and_center``); the member turns these into offsets
(:meth:`DetailBrush.offsets`) scaled by ``b`` = strength × pressure. Mirror symmetry: one pass
per mirror image, each from the surface the previous left. All arithmetic is NumPy in a fixed
order (no threads, no BLAS sums): a replay is bit for bit on any machine.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from gogreen_core.mesh.topology import FaceAdjacency
from gogreen_core.sculpt.brushes.base import (
    Displacement,
    StrokeContext,
    mirror_signs,
    smooth_cutoff,
)
from gogreen_core.sculpt.brushes.paint import PAINT_AUTO_INFLUENCE, PaintBrush

if TYPE_CHECKING:
    from gogreen_core.mesh.mesh_state import MeshState
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent

__all__ = ["DAB_SPACING", "MAX_DABS", "Dab", "DetailBrush", "dab_offsets", "dot3"]

#: Distance between dabs along a stroke, as a fraction of the brush radius R (Blender's
#: default spacing, 10 %).
DAB_SPACING = 0.1
#: Most dabs one event makes (a longer segment spaces them further apart).
MAX_DABS = 256
#: Where the stroke's dab spacing is kept between events (:attr:`StrokeContext.stroke`).
_TRAVEL = "detail travel"
_DIRECTION = "detail direction"


def dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products over the last axis (of length 3) of ``a`` and ``b`` ((n, 3) or (3,)),
    written out: BLAS sums may round differently per machine (see the module docstring)."""
    return cast(np.ndarray, a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2])


def dab_offsets(length: float, spacing: float, travel: float | None) -> tuple[np.ndarray, float]:
    """Where the dabs of a segment of ``length`` fall (distances along it, ascending), and
    the distance travelled since the last one at its end. ``travel``: the distance since the
    previous dab (None: the stroke's first event, whose start is a dab). At most
    :data:`MAX_DABS` (spaced further apart on a longer segment)."""
    if travel is None:
        first, travel = 0.0, spacing
    else:
        first = spacing - travel
    if length < first:
        return np.zeros(0), travel + length
    count = min(int((length - first) // spacing) + 1, MAX_DABS)
    if count == MAX_DABS:
        spacing = max(spacing, (length - first) / (MAX_DABS - 1))
    at = first + spacing * np.arange(count)
    at = at[at <= length]
    return at, float(length - at[-1])


@dataclass(frozen=True)
class Dab:
    """What one dab of one mirror pass sees, in the stroke's side of the mirror planes.

    points : (n, 3) the region's vertices (the whole event's candidates).
    weight : (n,) the falloff of their distance to the dab centre, 0 beyond ``radius``.
    normals : (n, 3) unit vertex normals where ``weight`` > 0 (zero rows elsewhere).
    center : (3,) the dab's centre (on the swept segment).
    area_normal : (3,) unit, the weighted mean of the normals (Blender's area normal).
    area_center : (3,) the weighted mean of the points.
    direction : (3,) unit stroke direction (zero before the cursor has moved).
    radius : R, model units.
    amount : strength × pen pressure, negative inverted (Ctrl).
    """

    points: np.ndarray
    weight: np.ndarray
    normals: np.ndarray
    center: np.ndarray
    area_normal: np.ndarray
    area_center: np.ndarray
    direction: np.ndarray
    radius: float
    amount: float


class DetailBrush(PaintBrush):
    """A paint brush acting in dabs (see the module docstring); members give
    :meth:`offsets`."""

    #: Candidate vertices lie within this many R of the segment (clay strips' square reaches
    #: its corners).
    select_factor: float = 1.0

    def radius(self, ctx: StrokeContext, brush: Brush) -> float:
        """R (model units): the brush's influence radius (2 ε automatic; an infinite influence
        counts as the automatic one: a dab is local)."""
        reach = self.reach(ctx, brush)
        if math.isinf(reach):
            reach = PAINT_AUTO_INFLUENCE
        return reach * brush.eps(ctx.model_size)

    @abstractmethod
    def offsets(self, dab: Dab) -> np.ndarray:
        """The motion (n, 3) one dab gives ``dab.points`` (in the dab's mirror frame)."""

    def displace(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> Displacement:
        mesh = ctx.mesh
        radius = self.radius(ctx, brush)
        signs = mirror_signs(brush.symmetry)
        rows = mesh.rows_near(event.center, event.delta, self.select_factor * radius, signs)
        out = ctx.rows(len(rows))
        out[:] = mesh.vertices[rows]
        amount = brush.strength * event.acting_amount
        memo: dict[str, Any] = {} if ctx.stroke is None else ctx.stroke
        length = float(np.linalg.norm(event.delta))
        at, memo[_TRAVEL] = dab_offsets(length, DAB_SPACING * radius, memo.get(_TRAVEL))
        if length > 0:
            memo[_DIRECTION] = event.delta / length
        direction = np.asarray(memo.get(_DIRECTION, np.zeros(3)), dtype=np.float64)
        if not len(rows) or amount == 0 or not len(at):
            return Displacement(rows, out)
        slot = np.full(len(mesh.vertices), -1, dtype=np.int64)
        slot[rows] = np.arange(len(rows))
        unit = event.delta / length if length > 0 else np.zeros(3)
        origin = mesh.origin
        motion = np.empty_like(out)
        for s in at:
            center = event.center + s * unit
            motion[:] = 0.0
            for sign in signs:  # every pass sees the surface the previous dab left
                points = origin + sign * (out - origin)
                gap = points - center
                weight = smooth_cutoff(np.sqrt(dot3(gap, gap)), 0.0, radius)
                inside = np.flatnonzero(weight > 0)
                if not len(inside):
                    continue
                normals = np.zeros_like(points)
                normals[inside] = sign * _vertex_normals(mesh, rows[inside], slot, out)
                w = weight[inside]
                area = (w[:, None] * normals[inside]).sum(axis=0)
                size = float(np.linalg.norm(area))
                if not size > 0:
                    continue
                dab = Dab(
                    points,
                    weight,
                    normals,
                    center,
                    area / size,
                    (w[:, None] * points[inside]).sum(axis=0) / w.sum(),
                    direction,
                    radius,
                    amount,
                )
                motion += sign * self.offsets(dab)
            out += motion
        return Displacement(rows, out)


def _vertex_normals(
    mesh: MeshState, rows: np.ndarray, slot: np.ndarray, current: np.ndarray
) -> np.ndarray:
    """Area-weighted unit normals (k, 3) of vertices ``rows`` (k,), with the positions
    ``current[slot[v]]`` where ``slot[v]`` ≥ 0, else ``mesh.vertices[v]``."""
    owner, around = FaceAdjacency.of(mesh.faces, len(mesh.vertices)).around(rows)
    corners = mesh.faces[around]
    where = slot[corners]
    p = np.where((where >= 0)[..., None], current[np.maximum(where, 0)], mesh.vertices[corners])
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    out = np.empty((len(rows), 3))
    for axis in range(3):
        out[:, axis] = np.bincount(owner, face[:, axis], minlength=len(rows))
    norm = np.linalg.norm(out, axis=1)
    norm[norm == 0] = 1.0
    return cast(np.ndarray, out / norm[:, None])
