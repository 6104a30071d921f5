"""What the current brush would do, before the stroke: its field for a unit drag at the cursor
(the app colours the surface by it while the cursor hovers: View → Field preview), so the
material's effect shows before the stroke. One evaluation of the field, no integration.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.sculpt.brushes import Brush, BrushEvent, GreenBrush, mirror_signs
from gogreen_core.sculpt.constraints import smooth_cutoff
from gogreen_core.sculpt.material_frame import FramedKernels
from gogreen_core.sculpt.stroke import surface_frame_of

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["FieldPreview", "field_preview"]


@dataclass(frozen=True)
class FieldPreview:
    """A brush's field at the vertices it reaches.

    rows : (n,) int64, the vertices within its influence (and its mirror images').
    velocity : (n, 3), u per unit drag (grab brushes: as a fraction of the cursor motion;
        affine brushes: in ε per unit amount).
    motion : (n,) ≥ 0, |u|.
    """

    rows: np.ndarray
    velocity: np.ndarray
    motion: np.ndarray


def field_preview(
    sculptor: Sculptor,
    brush: Brush,
    center: np.ndarray,
    axis: np.ndarray,
    direction: np.ndarray,
) -> FieldPreview | None:
    """The field of ``brush`` for a unit drag at ``center`` (3,) on the surface, seen along the
    view ``axis`` (3,), the drag along ``direction`` (3,) (projected ⟂ the axis); None for a
    brush without a Green's function field (or a drag along the axis)."""
    behaviour = brush.type
    if not isinstance(behaviour, GreenBrush):
        return None
    axis = np.asarray(axis, dtype=np.float64)
    axis = axis / np.linalg.norm(axis)
    drag = np.asarray(direction, dtype=np.float64)
    drag = drag - (drag @ axis) * axis
    if not np.linalg.norm(drag) > 0:
        return None
    drag = drag / np.linalg.norm(drag)
    eps = brush.eps(sculptor.model_size)
    unit = eps if not behaviour.is_affine else 1.0
    event = BrushEvent(center, delta=eps * drag, amount=1.0, axis=axis, direction=drag)
    driver, kernels = sculptor._strokes, sculptor._kernels  # the engine's own stroke step
    if kernels.settings.material_frame == "surface":  # as a stroke starting here would turn it
        kernels = FramedKernels(kernels, surface_frame_of(driver.mesh, brush, event))
    ctx = driver.context(kernels)
    field = behaviour.field(ctx, brush, event)
    cutoff = brush.cutoff(sculptor.model_size, field.reach)
    signs = mirror_signs(brush.symmetry)
    mesh = ctx.mesh
    rows = mesh.rows_near(field.center, np.zeros(3), None if cutoff is None else cutoff[1], signs)
    points = mesh.vertices[rows]
    velocity = np.zeros_like(points)
    for sign in signs:  # v(x) = Σ_M M s(|y − c|) u(y − c), y = o + M (x − o)
        identity = bool(np.all(sign == 1.0))
        mirrored = points if identity else mesh.origin + sign * (points - mesh.origin)
        if behaviour.is_affine:
            u = field.kernel.affine_displacement(mirrored, field.center, field.load)
        else:
            u = field.kernel.displacement(mirrored, field.center, field.load)
        if cutoff is not None:  # only the rows past its start: most of a big mesh is inside
            offsets = mirrored - field.center
            distance = np.sqrt(np.einsum("ij,ij->i", offsets, offsets))
            fading = np.flatnonzero(distance > cutoff[0])
            u[fading] *= smooth_cutoff(distance[fading], *cutoff)[:, None]
        velocity += u if identity else sign * u
    velocity /= unit
    if mesh.masked:  # a stroke moves a vertex (1 − mask) of the way
        velocity *= (1.0 - mesh.mask[rows])[:, None]
    return FieldPreview(rows, velocity, np.sqrt(np.einsum("ij,ij->i", velocity, velocity)))
