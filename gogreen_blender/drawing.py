"""The brush circle in the 3D view: where the brush acts and how far it reaches.

Two rings facing the view around the brush point: ε (the brush radius, solid) and the influence
radius (where motion fades to zero, fainter). :func:`ring_points` is plain NumPy (tested);
the drawing itself needs a window's GPU context (``gpu`` is not available in background mode).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CursorState", "cursor", "draw_cursor", "draw_radial", "ring_points", "set_cursor"]

#: Identifier of the GoGreen Sculpt tool (the circle shows while it is active).
TOOL_ID = "gogreen.sculpt_tool"
#: Segments of a ring.
SEGMENTS = 64
RING_COLOR = (1.0, 0.55, 0.1, 0.9)
INFLUENCE_COLOR = (1.0, 0.55, 0.1, 0.35)


@dataclass(frozen=True)
class CursorState:
    """World-space brush circle: ``center`` (3,), unit ``right`` and ``up`` (3,) spanning the
    view plane, ``radius`` ε and ``reach`` (influence radius; inf: none drawn)."""

    center: np.ndarray
    right: np.ndarray
    up: np.ndarray
    radius: float
    reach: float


def ring_points(
    center: np.ndarray, right: np.ndarray, up: np.ndarray, radius: float, segments: int = SEGMENTS
) -> np.ndarray:
    """(segments + 1, 3) closed polyline of the circle of ``radius`` about ``center`` in the
    plane of ``right`` and ``up`` (unit, orthogonal)."""
    t = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    return (
        np.asarray(center, float)
        + radius * np.cos(t)[:, None] * np.asarray(right, float)
        + radius * np.sin(t)[:, None] * np.asarray(up, float)
    )


_cursor: CursorState | None = None


def set_cursor(state: CursorState | None) -> None:
    """Show the circle at ``state`` (None hides it); the caller redraws the region."""
    global _cursor
    _cursor = state


def cursor() -> CursorState | None:
    return _cursor


def draw_cursor() -> None:
    """SpaceView3D POST_VIEW draw handler (needs a GPU context: not in background mode); draws
    while the GoGreen tool is the active one."""
    state = _cursor
    if state is None:
        return
    import bpy

    context = bpy.context
    tool = context.workspace.tools.from_space_view3d_mode(context.mode, create=False)
    if tool is None or tool.idname != TOOL_ID:
        return
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    viewport = gpu.state.viewport_get()
    shader.uniform_float("viewportSize", (viewport[2], viewport[3]))
    gpu.state.blend_set("ALPHA")
    rings = [(state.radius, RING_COLOR, 2.0)]
    if np.isfinite(state.reach):
        rings.append((state.reach, INFLUENCE_COLOR, 1.0))
    for radius, color, width in rings:
        points = ring_points(state.center, state.right, state.up, radius)
        batch = batch_for_shader(shader, "LINE_STRIP", {"pos": points.astype(np.float32)})
        shader.uniform_float("lineWidth", width)
        shader.uniform_float("color", color)
        batch.draw(shader)
    gpu.state.blend_set("NONE")


def draw_radial(control) -> None:
    """SpaceView3D POST_PIXEL draw handler of an F / Shift+F drag: its circle in region
    pixels (a :class:`~.radial.RadialControl`)."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    viewport = gpu.state.viewport_get()
    shader.uniform_float("viewportSize", (viewport[2], viewport[3]))
    gpu.state.blend_set("ALPHA")
    center = np.array([control.center[0], control.center[1], 0.0])
    points = ring_points(center, np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), control.pixels)
    batch = batch_for_shader(shader, "LINE_STRIP", {"pos": points[:, :2].astype(np.float32)})
    shader.uniform_float("lineWidth", 2.0)
    shader.uniform_float("color", RING_COLOR)
    batch.draw(shader)
    gpu.state.blend_set("NONE")
