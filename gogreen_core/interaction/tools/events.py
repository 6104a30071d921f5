"""What the tools take and give: pointer samples in, updates for the view out."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gogreen_core.interaction.tools.gauge import tangent_frame
from gogreen_core.sculpt.brushes import DEFAULT_INFLUENCE

__all__ = ["CursorState", "PointerEvent", "ToolUpdate"]


@dataclass(frozen=True)
class PointerEvent:
    """One pointer sample in plain numbers.

    screen : (x, y) widget pixels, x right, y down.
    point : (3,) world point: the picked surface point (press, hover), or the cursor on the
        drag plane through the press point (moves during a drag); None when nothing is hit.
    normal : (3,) surface normal at ``point`` when it was picked, else None.
    view_dir : (3,) unit direction from the camera into the screen.
    screen_x : (3,) unit world direction of the screen's x axis.
    pressure : pen pressure in [0, 1] (1 for a mouse); scales the step of a stroke.
    modifiers : names of held modifier keys ("shift", "ctrl", "alt").
    """

    screen: tuple[float, float]
    point: np.ndarray | None = None
    normal: np.ndarray | None = None
    view_dir: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -1.0]))
    screen_x: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    pressure: float = 1.0
    modifiers: frozenset[str] = frozenset()


@dataclass(frozen=True)
class CursorState:
    """Where the brush cursor is drawn: ``center`` (3,), unit ``normal`` (3,), ``radius`` ε
    (model units), ``influence`` (the moved region's radius in multiples of ε), ``profile``
    (samples over [0, influence · ε] of the relative motion, :func:`brush_profile`, or None),
    ``label`` (a live value shown while F / Shift+F drags it, else None) and ``full_radius``
    (during a pen stroke whose pressure shrinks the radius: the brush's own ε, model units,
    drawn faintly around the pressed one; else None) and ``moving_radius`` (model units: the
    region that moves by a tenth of the motion or more,
    :func:`gogreen_core.interaction.tools.moving_radius`; what the ring shows, None when
    unknown) and ``axes`` (3, 3), rows: the material's main directions where the cursor rests,
    scaled 0-1 (:func:`~gogreen_core.interaction.tools.material_axes.cursor_axes`), None for an
    isotropic material; ``detail`` (model units: while dynamic topology is on, the edge length it
    remeshes to, drawn as a small circle of that diameter at the centre; else None);
    ``gauge`` (K, 3) and ``gauge_spokes`` (S, P, 3) (model units: while an anchored brush acts,
    where the marks set at the press on the circle of radius ε about the press point, and along
    a few spokes from it, are now: they move with the surface,
    :class:`~gogreen_core.interaction.tools.gauge.DeformationGauge`; else None)."""

    center: np.ndarray
    normal: np.ndarray
    radius: float
    influence: float = DEFAULT_INFLUENCE
    profile: np.ndarray | None = None
    label: str | None = None
    full_radius: float | None = None
    moving_radius: float | None = None
    axes: np.ndarray | None = None
    detail: float | None = None
    gauge: np.ndarray | None = None
    gauge_spokes: np.ndarray | None = None

    def ring_matrix(self) -> np.ndarray:
        """(4, 4) transform placing the unit circle of the xy plane on the surface (lifted by
        1e-3 radius along the normal so the surface does not hide it)."""
        n, t1, t2 = tangent_frame(self.normal)
        matrix = np.eye(4)
        matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = t1 * self.radius, t2 * self.radius, n
        matrix[:3, 2] *= self.radius
        matrix[:3, 3] = np.asarray(self.center, dtype=float) + 1e-3 * self.radius * n
        return matrix


@dataclass
class ToolUpdate:
    """What one call of the tools changed, for the view to draw.

    moved : indices of moved vertices (None: none moved; ``all_moved``: redraw every vertex).
    pins_changed : the constraint points changed.
    cursor : new brush-ring placement, or None to keep it (``hide_cursor`` hides it).
    step_seconds : wall time of the engine call, 0 if none ran.
    error : message of an engine error (the stroke was cancelled and the mesh restored).
    refused : the press was refused before reaching the engine (``error`` says why).
    note : what the artist should know that is no error (a stroke that changed nothing).
    """

    moved: np.ndarray | None = None
    all_moved: bool = False
    pins_changed: bool = False
    cursor: CursorState | None = None
    hide_cursor: bool = False
    step_seconds: float = 0.0
    error: str | None = None
    refused: bool = False
    note: str | None = None

    @property
    def changed(self) -> bool:
        return bool(
            self.moved is not None
            or self.all_moved
            or self.pins_changed
            or self.cursor is not None
            or self.hide_cursor
            or self.error
            or self.note
        )
