"""The brush cursor: where the ring is drawn, the falloff profile it shows, and the on-screen
drags of the radius and strength (Blender's F / Shift+F)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.interaction.tools.events import CursorState
from gogreen_core.sculpt.brushes import CUTOFF_START, DEFAULT_INFLUENCE
from gogreen_core.sculpt.brushes.table import brush_row, brush_type
from gogreen_core.sculpt.constraints import smooth_cutoff
from gogreen_core.threads import threads_at_most

if TYPE_CHECKING:
    from gogreen_core.interaction.tools.sculpt import SculptTools
    from gogreen_core.sculpt.brushes.affine import AffineBrush

__all__ = [
    "MOVING_FRACTION",
    "PIXELS_PER_STRENGTH",
    "PROFILE_SAMPLES",
    "CursorController",
    "ValueDrag",
    "anchored_label",
    "brush_profile",
    "felt_profile",
    "grab_motion",
    "moving_radius",
]

#: Pixels from the cursor centre that mean strength 1 in a Shift+F drag with no cursor shown.
PIXELS_PER_STRENGTH = 100.0

#: Samples of the falloff profile drawn in the brush cursor, over [0, influence · ε].
PROFILE_SAMPLES = 48
#: The cursor's ring shows the region that moves by at least this fraction of the motion.
MOVING_FRACTION = 0.1
#: Samples of :func:`moving_radius` over [0, influence · ε], then between the two around it.
_RING_SAMPLES = 96
_FINE_SAMPLES = 24
#: The reach (in ε) searched for the ring of a brush without a finite influence.
_UNBOUNDED_REACH = 32.0


def anchored_label(kind: str) -> str:
    """The label of anchored brush ``kind``'s cursor while it acts (its row's ``acting``)."""
    acting = brush_row(kind).acting or kind.replace("_", " ")
    return f"{acting} about the press point"


def brush_profile(kernel: GreenKernel | None, influence: float, eps: float) -> np.ndarray:
    """Relative motion (PROFILE_SAMPLES,) in [0, 1] at distances ``linspace(0, influence · ε)``
    from a grab of ``kernel`` (at ε = ``eps``): :func:`grab_motion` times the smooth cutoff of
    an ``influence`` of that many ε, over its largest value; the cutoff alone if ``kernel`` is
    None (kernels not ready)."""
    finite = np.isfinite(influence)
    outer = (influence if finite else DEFAULT_INFLUENCE) * eps
    r = np.linspace(0.0, outer, PROFILE_SAMPLES)
    cutoff = smooth_cutoff(r, CUTOFF_START * outer, outer) if finite else 1.0
    if kernel is None:
        return np.broadcast_to(cutoff, r.shape).astype(float)
    motion = grab_motion(kernel, r) * cutoff
    peak = motion.max()
    return motion / peak if peak > 0 and np.isfinite(peak) else np.zeros(PROFILE_SAMPLES)


def moving_radius(
    kernel: GreenKernel | None, influence: float, eps: float, anchored: bool = False
) -> float:
    """Radius (model units) of the region that moves by at least :data:`MOVING_FRACTION` of
    the motion (what the cursor's ring shows): the largest r ≤ influence · ε where
    :func:`_motion_envelope` of ``kernel`` at ε = ``eps`` times the smooth cutoff is at least
    that fraction of its peak; the cutoff alone if ``kernel`` is None."""
    reach = influence if np.isfinite(influence) else _UNBOUNDED_REACH
    outer = reach * eps

    def motion(r: np.ndarray) -> np.ndarray:
        cutoff = smooth_cutoff(r, CUTOFF_START * outer, outer) if np.isfinite(influence) else 1.0
        relative = np.broadcast_to(cutoff, r.shape).astype(float)
        if kernel is not None:
            relative = relative * _motion_envelope(kernel, r, anchored)
        return relative

    r = np.linspace(0.0, outer, _RING_SAMPLES)
    coarse = motion(r)
    peak = float(coarse.max())
    if not (peak > 0 and np.isfinite(peak)):
        return float(eps)
    level = MOVING_FRACTION * peak
    last = int(np.flatnonzero(coarse >= level)[-1])
    if last + 1 >= len(r):
        return float(r[-1])
    fine_r = np.linspace(r[last], r[last + 1], _FINE_SAMPLES)
    fine = motion(fine_r)
    above = np.flatnonzero(fine >= level)
    i = int(above[-1]) if len(above) else 0
    if i + 1 >= len(fine_r):
        return float(fine_r[-1])
    # where the motion crosses the level, between the last sample above and the next
    a, b = fine[i], fine[i + 1]
    t = (a - level) / (a - b) if a > b else 0.0
    return float(fine_r[i] + t * (fine_r[i + 1] - fine_r[i]))


def _directions() -> np.ndarray:
    """(13, 3) unit directions up to sign: the cube's axes, face and body diagonals."""
    steps = np.array(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1])).reshape(3, -1).T
    halves = np.array([d for d in steps if tuple(d) > (0, 0, 0)], dtype=float)
    return cast(np.ndarray, halves / np.linalg.norm(halves, axis=1)[:, None])


def _motion_envelope(kernel: GreenKernel, distances: np.ndarray, anchored: bool) -> np.ndarray:
    """The largest motion (n,) at ``distances`` over :func:`_directions`: of a unit grab
    (‖G(r d̂) G(0)⁻¹‖₂) or, ``anchored``, of an affine load (‖∇G(r d̂)‖)."""
    directions = _directions()
    points = (distances[:, None, None] * directions[None]).reshape(-1, 3)
    with threads_at_most(1):
        if anchored:
            values = kernel.green_gradient(points).reshape(len(distances), len(directions), -1)
            return cast(np.ndarray, np.linalg.norm(values, axis=2).max(axis=1))
        green = kernel.green(points).reshape(len(distances), len(directions), 3, 3)
        centre = kernel.green(np.zeros((1, 3)))[0]
    normalized = _relative(green, centre)
    return cast(np.ndarray, np.linalg.norm(normalized, ord=2, axis=(2, 3)).max(axis=1))


def _relative(green: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """``green`` (..., 3, 3) times G(0)⁻¹ = ``centre``⁻¹, or (R₀(0) = 0) over its largest entry."""
    try:
        return green @ np.linalg.inv(centre)
    except np.linalg.LinAlgError:
        return cast(np.ndarray, green / (np.abs(green).max() or 1.0))


def grab_motion(kernel: GreenKernel, distances: np.ndarray) -> np.ndarray:
    """Motion (n,) at ``distances`` (n,) along x̂ from a unit grab of ``kernel``:
    |G(r x̂) G(0)⁻¹ e| averaged over the three axes e, 1 at the centre (G(0) singular: G over
    its largest entry). On the calling thread alone: for a few dozen samples a second numba
    thread only adds its wake-up (3-7 ms)."""
    offsets = np.zeros((len(distances), 3))
    offsets[:, 0] = distances
    with threads_at_most(1):
        green = kernel.green(offsets)  # (n, 3, 3)
    return cast(np.ndarray, np.linalg.norm(_relative(green, green[0]), axis=1).mean(axis=1))


#: Directions (in the plane ⟂ the view axis) an affine brush's felt profile averages over.
_FELT_DIRECTIONS = 8


def felt_profile(kind: str, kernel: GreenKernel | None, rho: np.ndarray) -> np.ndarray | None:
    """What brush ``kind`` feels like along a radius: its motion (n,) at ``rho`` (n,) brush
    radii from its centre, 1 at its peak; None when it is zero or not finite. ``kernel``: the
    brush's own at ε = 1 (:meth:`GreenBrush.unit_kernel`; None for a paint brush). Grab
    brushes: :func:`grab_motion`; affine ones: |u| of their load (a view along z, a drag along
    x) averaged over directions in the view plane; paint ones: their cutoff weight."""
    rho = np.asarray(rho, dtype=np.float64)
    brush = brush_type(kind)
    if brush.family == "paint" or kernel is None:
        outer = brush.auto_reach
        values = smooth_cutoff(rho, CUTOFF_START * outer, outer)
    elif brush.is_affine:
        load = cast("AffineBrush", brush).shape(None, np.array([1.0, 0.0, 0.0]))
        angles = np.linspace(0.0, np.pi, _FELT_DIRECTIONS, endpoint=False)
        directions = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1)
        points = (rho[:, None, None] * directions[None]).reshape(-1, 3)
        with threads_at_most(1):
            motion = kernel.affine_displacement(points, np.zeros(3), load)
        values = np.linalg.norm(motion, axis=1).reshape(len(rho), -1).mean(axis=1)
    else:
        values = grab_motion(kernel, rho)
    peak = values.max() if len(values) else 0.0
    return values / peak if np.isfinite(peak) and peak > 0 else None


@dataclass
class ValueDrag:
    """An on-screen drag of the brush radius or strength (Blender's F / Shift+F): ``value =
    start · distance / start_distance`` (screen pixels from the cursor centre ``center``),
    clipped to ``[low, high]``, so the ring's edge follows the pointer for the radius."""

    name: str
    start: float
    center: tuple[float, float]
    start_distance: float
    low: float
    high: float

    def __post_init__(self) -> None:
        if self.name not in ("radius", "strength"):
            raise ValueError(f"a value drag is of radius or strength (got {self.name!r})")
        self.start_distance = max(float(self.start_distance), 1.0)
        self.value = float(self.start)

    def move(self, screen: tuple[float, float]) -> float:
        distance = float(np.hypot(screen[0] - self.center[0], screen[1] - self.center[1]))
        self.value = min(max(self.start * distance / self.start_distance, self.low), self.high)
        return self.value

    @property
    def label(self) -> str:
        return f"{self.name.capitalize()} {self.value:.3g}"


class CursorController:
    """The brush cursor of ``tools``: on the surface under the hovering cursor, where the brush
    acts while dragging, hidden off the model; its measures are the tools' ``_cursor_*``."""

    def __init__(self, tools: SculptTools) -> None:
        self.tools = tools
        self.state: CursorState | None = None
        self._normal: np.ndarray | None = None

    def place(
        self,
        point: np.ndarray | None,
        normal: np.ndarray | None,
        label: str | None = None,
        gauge: tuple[np.ndarray | None, np.ndarray | None] | None = None,
    ) -> CursorState | None:
        """The cursor at ``point`` (None hides it), ``normal`` (None: the last one), with a
        ``label`` and an anchored stroke's ``gauge`` (loop, spokes)."""
        if point is None:
            self.state = None
            return None
        if normal is not None:
            self._normal = np.asarray(normal, dtype=float)
        n = self._normal if self._normal is not None else np.array([0.0, 0.0, 1.0])
        center, tools = np.array(point, dtype=float), self.tools
        self.state = CursorState(
            center,
            n,
            float(tools._cursor_radius()),
            float(tools._cursor_influence()),
            tools._cursor_profile(),
            label,
            tools._cursor_full_radius(),
            tools._cursor_moving_radius(),
            tools._cursor_axes(center),
            tools._cursor_detail(),
            *(gauge or (None, None)),
        )
        return self.state

    def refresh(self) -> CursorState | None:
        """The same place with the current radius, influence and profile (None if hidden)."""
        state = self.state
        if state is None:
            return None
        gauge = (state.gauge, state.gauge_spokes)
        return self.place(state.center, state.normal, state.label, gauge)

    def hide(self) -> None:
        """Hidden until the pointer moves again (after undo, or a newly opened file)."""
        self.state = None
