"""What the tools take and give: pointer samples in, updates for the view out."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gogreen_core.interaction.tools.gauge import tangent_frame
from gogreen_core.sculpt.brushes import DEFAULT_INFLUENCE

__all__ = ["CursorState", "PointerEvent", "ToolUpdate"]


@dataclass(frozen=True)
class PointerEvent:
    """One pointer sample: ``screen`` (x, y) widget pixels (y down); ``point`` (3,) the picked
    surface point, or during a drag the cursor on the drag plane (None: nothing hit);
    ``normal`` (3,) the surface normal when picked; ``view_dir`` (3,) unit, camera into the
    screen; ``screen_x`` (3,) the screen's x axis in the world; ``pressure`` in [0, 1] (1 for a
    mouse); ``modifiers`` held ("shift", "ctrl", "alt")."""

    screen: tuple[float, float]
    point: np.ndarray | None = None
    normal: np.ndarray | None = None
    view_dir: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -1.0]))
    screen_x: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    pressure: float = 1.0
    modifiers: frozenset[str] = frozenset()


@dataclass(frozen=True)
class CursorState:
    """Where the brush cursor is drawn (lengths in model units; None: not drawn):

    center, normal : (3,) and unit (3,). radius : ε. influence : in multiples of ε.
    profile : relative motion over [0, influence · ε] (:func:`brush_profile`).
    label : the live value of an F / Shift+F drag, or an anchored brush's action.
    full_radius : the brush's own ε while pen pressure shrinks it.
    moving_radius : the region moving by a tenth of the motion or more (:func:`moving_radius`).
    axes : (3, 3) rows, the material's main directions, scaled 0-1 (``cursor_axes``).
    detail : dynamic topology's edge length while it is on.
    gauge, gauge_spokes : (K, 3) and (S, P, 3), an anchored stroke's marks moving with the
        surface (:class:`~gogreen_core.interaction.tools.gauge.DeformationGauge`).
    """

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
        matrix[:3, :3] = np.stack([t1, t2, n], axis=1) * self.radius
        matrix[:3, 3] = np.asarray(self.center, dtype=float) + 1e-3 * self.radius * n
        return matrix


@dataclass
class ToolUpdate:
    """What one call of the tools changed, for the view to draw: ``moved`` vertex indices
    (``all_moved``: every vertex), ``pins_changed``, a new ``cursor`` placement (None: keep it;
    ``hide_cursor``), ``step_seconds`` of the engine call, an engine ``error`` (the stroke was
    cancelled), ``refused`` (the press never reached the engine), a ``note`` for the artist."""

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
        flags = (self.all_moved, self.pins_changed, self.hide_cursor, self.error, self.note)
        return self.moved is not None or self.cursor is not None or any(flags)
