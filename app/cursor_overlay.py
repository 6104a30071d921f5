"""The brush cursor as a 2D overlay: VTK 2D actors drawn after the scene, never hidden by it.

It shows, around the screen position of the point where the brush acts: the region that moves
by a tenth of the motion or more (a solid ring,
:func:`gogreen_core.interaction.tools.moving_radius`; about ε for the grab of key 1, many ε for the
wide grab), the influence radius (influence · ε, a thin ring: nothing beyond it moves), a text label
(a live value while F / Shift+F drags it; "scaling about the press point" while an affine brush
acts) and, while pen pressure shrinks the radius, a faint ring at the brush's full radius (as
Blender draws it). The falloff profile (the relative motion against the distance from the centre, a
curve over the ε ring's diameter, 1 at the centre rising to ε) is drawn only while F drags the
radius, or at all times when asked (:attr:`CursorOverlay.profile_always`, View → Falloff Profile):
otherwise it would cross the model under every hover. The rings' screen sizes come from projecting
the world radius at the point, so they match what the brush does at that depth; the geometry is
rebuilt at every render (a renderer ``StartEvent``) so orbiting and zooming keep it in place.

An anisotropic material also shows its main directions where the cursor rests (the material
panel's glyph put on the surface, :attr:`CursorState.axes`): three short lines through the
centre, red, green and blue for its first (stiffest), second and third axes, each reaching
:data:`AXIS_REACH` of the solid ring (at most 3 ε) times E along it over the largest E, so an
artist sees which way the fibres, grain or layers will run before the stroke (with the
"surface" material frame they turn with the surface).

While an anchored (affine) brush acts, its deformation gauge (:attr:`CursorState.gauge`): marks
set at the press on the circle of radius ε about the press point, and four spokes, drawn where
the surface has taken them (a loop of dots and the spokes, bright on any matcap), over a faint
copy of that circle as it was: a twist turns the spokes, a stretch elongates the loop, a scale
grows it and a pinch draws it in, motions along the surface that shading hardly shows.
"""

from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkRenderingCore import vtkActor2D, vtkPolyDataMapper2D, vtkTextActor

from gogreen_core.interaction.tools import CursorState

__all__ = ["CursorOverlay", "PinOverlay", "pixel_radius", "ring_points", "to_display"]

CURSOR_COLOR = (1.0, 0.55, 0.1)
INFLUENCE_COLOR = (1.0, 0.8, 0.55)
PROFILE_COLOR = (1.0, 1.0, 1.0)
PIN_COLOR = (1.0, 0.2, 0.33)
#: How far the material's axes reach, as a fraction of the solid ring's radius.
AXIS_REACH = 0.8
#: The material's first, second and third axes (Blender's x, y, z colours).
AXIS_COLORS = ((0.95, 0.25, 0.3), (0.45, 0.85, 0.2), (0.25, 0.55, 1.0))
SEGMENTS = 96
GAUGE_COLOR = (0.2, 0.95, 1.0)
#: Pixel radius of the gauge's dots.
GAUGE_DOT_PIXELS = 3.0
#: The detail circle is drawn at least this wide (pixels of radius), however fine the edges.
MIN_DETAIL_PIXELS = 2.0


def ring_points(center: tuple[float, float], radius: float, segments: int = SEGMENTS) -> np.ndarray:
    """(segments + 1, 3) display points of a closed circle (z = 0)."""
    t = np.linspace(0.0, 2 * np.pi, segments + 1)
    return np.column_stack(
        [center[0] + radius * np.cos(t), center[1] + radius * np.sin(t), np.zeros_like(t)]
    )


def to_display(renderer, point: np.ndarray) -> np.ndarray:
    """Display coordinates (x, y in pixels, y up; z the depth in [0, 1]) (3,) of the world
    ``point`` (3,) through ``renderer``'s current camera."""
    renderer.SetWorldPoint(*point, 1.0)
    renderer.WorldToDisplay()
    return np.array(renderer.GetDisplayPoint())


def pixel_radius(renderer, center: np.ndarray, radius: float) -> float:
    """Screen radius (pixels) of a world ``radius`` at world ``center`` (3,) through
    ``renderer``'s camera: the projection of a radius perpendicular to the view."""
    camera = renderer.GetActiveCamera()
    view = np.array(camera.GetFocalPoint()) - np.array(camera.GetPosition())
    side = np.cross(view, np.array(camera.GetViewUp()))
    norm = np.linalg.norm(side)
    side = side / norm if norm > 0 else np.array([1.0, 0.0, 0.0])
    a, b = to_display(renderer, center), to_display(renderer, center + radius * side)
    return float(np.hypot(*(b - a)[:2]))


class _Polyline2D:
    """One polyline actor in display coordinates (pixels, y up)."""

    def __init__(self, renderer, color, width: float, opacity: float = 1.0):
        self.polydata = vtkPolyData()
        mapper = vtkPolyDataMapper2D()
        mapper.SetInputData(self.polydata)
        self.actor = vtkActor2D()
        self.actor.SetMapper(mapper)
        prop = self.actor.GetProperty()
        prop.SetColor(*color)
        prop.SetLineWidth(width)
        prop.SetOpacity(opacity)
        self.actor.SetPickable(False)
        self.actor.SetVisibility(False)
        renderer.AddViewProp(self.actor)

    def set(self, points: np.ndarray) -> None:
        self.set_many([points])

    def set_many(self, polylines: list[np.ndarray]) -> None:
        points = np.concatenate(polylines) if polylines else np.zeros((0, 3))
        vtk_points = vtkPoints()
        vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
        lines = vtkCellArray()
        start = 0
        for line in polylines:
            lines.InsertNextCell(len(line))
            for k in range(start, start + len(line)):
                lines.InsertCellPoint(k)
            start += len(line)
        self.polydata.SetPoints(vtk_points)
        self.polydata.SetLines(lines)
        self.polydata.Modified()


class CursorOverlay:
    """The brush cursor of a renderer: :meth:`show` a :class:`CursorState` (None hides it).

    ``screen`` holds, after each render, the display centre (x, y) and the pixel radii of the ε
    and influence rings (None while hidden), for tests and the F drag; ``full_pixels`` the
    pixel radius of the full-radius ring (None unless pen pressure shrinks the radius).
    ``suspended`` hides it without forgetting its state (a screenshot of the model only).
    ``profile_always`` draws the falloff profile at all times; ``profile_now`` draws it for the
    time being (an F drag of the radius).
    """

    def __init__(self, renderer):
        self.renderer = renderer
        self.state: CursorState | None = None
        self.screen: tuple[tuple[float, float], float, float] | None = None
        self.full_pixels: float | None = None
        #: Pixel radius of the solid ring: the region that moves by a tenth of the motion or
        #: more (:attr:`CursorState.moving_radius`; ε when unknown). None while hidden.
        self.ring_pixels: float | None = None
        #: Pixel radius of the detail circle (dynamic topology's edge length as its diameter,
        #: at least :data:`MIN_DETAIL_PIXELS`), None unless dynamic topology is on.
        self.detail_pixels: float | None = None
        #: While True nothing is drawn; :attr:`state` is kept and drawn again once it is False.
        self.suspended = False
        self.profile_always = False
        self.profile_now = False
        self._influence = _Polyline2D(renderer, INFLUENCE_COLOR, 1.0, 0.6)
        self._full = _Polyline2D(renderer, CURSOR_COLOR, 1.0, 0.45)
        self._ring = _Polyline2D(renderer, CURSOR_COLOR, 2.5)
        self._profile = _Polyline2D(renderer, PROFILE_COLOR, 1.5, 0.85)
        self._axes = [_Polyline2D(renderer, color, 2.0, 0.95) for color in AXIS_COLORS]
        #: Display points (3, 2, 2) of the material's axes' ends after the last layout, or None.
        self.axes_screen: np.ndarray | None = None
        self._detail = _Polyline2D(renderer, CURSOR_COLOR, 1.5, 0.9)
        self._gauge_rest = _Polyline2D(renderer, PROFILE_COLOR, 1.0, 0.55)
        self._gauge = _Polyline2D(renderer, GAUGE_COLOR, 2.0)
        #: Display points (K, 2) of the gauge's loop after the last layout, or None.
        self.gauge_screen: np.ndarray | None = None
        self._text = vtkTextActor()
        self._text.GetTextProperty().SetFontSize(16)
        self._text.GetTextProperty().SetColor(*CURSOR_COLOR)
        self._text.GetTextProperty().BoldOn()
        self._text.SetVisibility(False)
        self._text.SetPickable(False)
        renderer.AddViewProp(self._text)
        renderer.AddObserver("StartEvent", lambda *_: self.layout())

    @property
    def visible(self) -> bool:
        return self.state is not None

    @property
    def profile_visible(self) -> bool:
        """The falloff profile is drawn (as of the last layout)."""
        return bool(self._profile.actor.GetVisibility())

    @property
    def label(self) -> str | None:
        """The label drawn beside the ring (as of the last layout), or None."""
        return str(self._text.GetInput()) if self._text.GetVisibility() else None

    def show(self, state: CursorState | None) -> None:
        """Draw ``state`` at the next render (None: hide)."""
        self.state = state
        self.layout()

    def layout(self) -> None:
        """Rebuild the 2D geometry for the current camera (cheap: a few hundred points)."""
        parts = (self._influence, self._ring, self._profile, self._full, self._detail, *self._axes)
        parts = (*parts, self._gauge, self._gauge_rest)
        self.full_pixels = self.detail_pixels = None
        self.gauge_screen = None
        self.axes_screen = None
        if self.state is None or self.suspended:
            for part in parts:
                part.actor.SetVisibility(False)
            self._text.SetVisibility(False)
            self.screen = self.ring_pixels = None
            return
        state = self.state
        center = np.asarray(state.center, dtype=float)
        display = to_display(self.renderer, center)
        xy = (float(display[0]), float(display[1]))
        eps_px = pixel_radius(self.renderer, center, state.radius)
        influence = state.influence if np.isfinite(state.influence) else 4.0
        outer_px = eps_px * influence
        # the ring shows the region that moves by a tenth of the motion or more
        moving = state.moving_radius
        ratio = moving / state.radius if moving and state.radius > 0 else 1.0
        self.ring_pixels = eps_px * ratio
        self._ring.set(ring_points(xy, self.ring_pixels))
        self._influence.set(ring_points(xy, outer_px))
        for part in (self._ring, self._influence):
            part.actor.SetVisibility(True)
        full = state.full_radius
        if full is not None and np.isfinite(full) and full > state.radius:
            self.full_pixels = self.ring_pixels * full / state.radius
            self._full.set(ring_points(xy, self.full_pixels))
        self._full.actor.SetVisibility(self.full_pixels is not None)
        # dynamic topology: a small circle as wide as the edges it remeshes to (Blender draws
        # its detail size on the cursor too)
        detail = state.detail
        if detail is not None and np.isfinite(detail) and detail > 0:
            edge_px = pixel_radius(self.renderer, center, detail)
            self.detail_pixels = max(MIN_DETAIL_PIXELS, 0.5 * edge_px)
            self._detail.set(ring_points(xy, self.detail_pixels, 24))
        self._detail.actor.SetVisibility(self.detail_pixels is not None)
        profile = self.profile_always or self.profile_now
        if profile and state.profile is not None and len(state.profile) > 1 and outer_px > 0:
            # mirrored profile over the diameter: height eps_px · motion(|x|)
            samples = np.asarray(state.profile, dtype=float)
            r = np.linspace(0.0, outer_px, len(samples))
            xs = np.concatenate([-r[::-1], r[1:]])
            ys = np.concatenate([samples[::-1], samples[1:]]) * eps_px
            self._profile.set(np.column_stack([xy[0] + xs, xy[1] + ys, np.zeros_like(xs)]))
            self._profile.actor.SetVisibility(True)
        else:
            self._profile.actor.SetVisibility(False)
        self._layout_axes(state, center, xy)
        self._layout_gauge(state)
        if state.label:
            self._text.SetInput(state.label)
            self._text.SetPosition(*self._label_position(xy))
            self._text.SetVisibility(True)
        else:
            self._text.SetVisibility(False)
        self.screen = (xy, eps_px, outer_px)

    def _layout_axes(self, state: CursorState, center: np.ndarray, xy: tuple[float, float]) -> None:
        """The material's axes: a line through the centre along each (±d: an axis has no
        sign), reaching :data:`AXIS_REACH` of the solid ring times its length (E along it over
        the largest E)."""
        axes = state.axes
        if axes is None:
            for part in self._axes:
                part.actor.SetVisibility(False)
            return
        # the solid ring's world radius, at most 3 ε (a wrinkle brush's ring is many ε wide)
        ring = min(state.moving_radius or state.radius, 3.0 * state.radius)
        ends = []
        for part, axis in zip(self._axes, np.asarray(axes, dtype=float), strict=True):
            tip = to_display(self.renderer, center + AXIS_REACH * ring * axis)[:2]
            tail = 2 * np.asarray(xy) - tip
            ends.append([tail, tip])
            line = np.array([[*tail, 0.0], [*tip, 0.0]])
            part.set(line)
            part.actor.SetVisibility(True)
        self.axes_screen = np.array(ends)

    def _layout_gauge(self, state: CursorState) -> None:
        """The deformation gauge: the loop through its marks (a dot at each) and the spokes
        where the surface has taken them, over the press-time circle of radius ε (faint)."""
        loop, spokes = state.gauge, state.gauge_spokes
        if loop is None or spokes is None or not len(loop):
            self._gauge.actor.SetVisibility(False)
            self._gauge_rest.actor.SetVisibility(False)
            return

        def project(points: np.ndarray) -> np.ndarray:
            shown = np.array([to_display(self.renderer, p) for p in points])
            shown[:, 2] = 0.0
            return shown

        marks = project(np.asarray(loop, dtype=float))
        self.gauge_screen = marks[:, :2].copy()
        lines = [np.concatenate([marks, marks[:1]])]
        lines += [project(np.asarray(spoke, dtype=float)) for spoke in spokes]
        lines += [ring_points((m[0], m[1]), GAUGE_DOT_PIXELS, 8) for m in marks]
        self._gauge.set_many(lines)
        circle = ring_points((0.0, 0.0), 1.0, SEGMENTS // 2)
        circle[:, 2] = 0.0
        world = np.column_stack([circle, np.ones(len(circle))]) @ state.ring_matrix().T
        self._gauge_rest.set(project(world[:, :3]))
        self._gauge.actor.SetVisibility(True)
        self._gauge_rest.actor.SetVisibility(True)

    def _label_position(self, xy: tuple[float, float]) -> tuple[float, float]:
        """Where the label goes: right of the ring, else left of it, else above its centre
        (an affine brush's ring can be wider than the view), always inside the view."""
        box = [0.0] * 4
        self._text.GetBoundingBox(self.renderer, box)
        width, height = box[1] - box[0], box[3] - box[2]
        view_w, view_h = self.renderer.GetSize()
        ring = self.ring_pixels or 0.0
        x, y = xy[0] + ring + 8, xy[1] + 8
        if x + width > view_w - 4:
            x = xy[0] - ring - 8 - width
        if x < 4:
            x, y = xy[0] - width / 2, xy[1] + ring + 8
        return (
            float(np.clip(x, 4, max(4.0, view_w - width - 4))),
            float(np.clip(y, 4, max(4.0, view_h - height - 4))),
        )


class PinOverlay:
    """The reach of every pin: a 2D ring (drawn over the surface) of the world radius beyond
    which the pin moves nothing, around each pin's screen position; rebuilt at every render."""

    def __init__(self, renderer):
        self.renderer = renderer
        self.points = np.zeros((0, 3))
        self.reach = 0.0
        #: Pixel radii of the rings after the last render.
        self.screen_radii: list[float] = []
        self._rings = _Polyline2D(renderer, PIN_COLOR, 1.5, 0.8)
        renderer.AddObserver("StartEvent", lambda *_: self.layout())

    def show(self, points: np.ndarray, reach: float) -> None:
        """Rings of world radius ``reach`` around ``points`` (k, 3); k = 0 hides them."""
        self.points = np.asarray(points, dtype=float).reshape(-1, 3)
        self.reach = float(reach)
        self.layout()

    def layout(self) -> None:
        if not len(self.points) or not np.isfinite(self.reach) or self.reach <= 0:
            self._rings.actor.SetVisibility(False)
            self.screen_radii = []
            return
        rings, radii = [], []
        for point in self.points:
            display = to_display(self.renderer, point)
            radius = pixel_radius(self.renderer, point, self.reach)
            rings.append(ring_points((display[0], display[1]), radius))
            radii.append(radius)
        self._rings.set_many(rings)
        self._rings.actor.SetVisibility(True)
        self.screen_radii = radii
