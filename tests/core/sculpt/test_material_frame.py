"""Materials that follow the surface (issue 35): with ``material_frame="surface"`` the same
stroke does the same thing anywhere on the model; mirror symmetry mirrors the frame."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gogreen_core.files.presets import builtin_presets
from gogreen_core.mesh.shapes import default_model, icosphere
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.material_frame import surface_frame
from gogreen_core.sculpt.sculptor import Sculptor

#: Half a turn about y: maps the default model's bounding box (centred at 0) onto itself, so
#: the model size and every ε stay the same.
TURN = np.diag([-1.0, 1.0, -1.0])


def _layered(frame: str) -> EngineSettings:
    preset = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    # turned arbitrarily, so that the half turn is no symmetry of the material
    material = preset.material.rotated(Rotation.from_euler("xyz", (0.4, -0.9, 0.3)).as_matrix())
    return preset.engine_settings().replace(material=material, material_frame=frame)


def _stroke(
    vertices: np.ndarray, faces: np.ndarray, settings: EngineSettings, kind: str, turn: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(vertices before, after) of one stroke of ``kind`` on the model turned by ``turn``."""
    start = vertices @ turn.T
    sculptor = Sculptor(start, faces, settings=settings)
    index = int(np.argmax(vertices @ np.array([0.3, 0.5, 0.8])))
    center = vertices[index]
    normal = center / np.linalg.norm(center)
    tangent = np.cross(normal, [1.0, 0.0, 0.0])
    tangent /= np.linalg.norm(tangent)
    size = sculptor.model_size
    if kind == "pinch":
        brush = Brush("pinch", radius=0.08)
        events = [
            BrushEvent(turn @ center, amount=0.05, axis=turn @ normal, direction=turn @ tangent)
            for _ in range(3)
        ]
    else:
        brush = Brush(kind, radius=0.06)
        step = 0.02 * size * (tangent + 0.5 * normal)
        events = [BrushEvent(turn @ (center + k * step), delta=turn @ step) for k in range(3)]
    sculptor.apply_brush(brush, events)
    return start, sculptor.vertices.copy()


@pytest.mark.parametrize("kind", ["grab", "pinch", "wrinkle"])
def test_surface_frame_makes_the_stroke_equivariant(kind: str) -> None:
    vertices, faces = default_model(4)
    gaps = {}
    for frame in ("surface", "world"):
        settings = _layered(frame)
        before, after = _stroke(vertices, faces, settings, kind, np.eye(3))
        _, turned = _stroke(vertices, faces, settings, kind, TURN)
        motion = np.linalg.norm(after - before, axis=1).max()
        assert motion > 1e-3 * np.ptp(vertices)
        gaps[frame] = np.abs(after @ TURN.T - turned).max() / motion
    assert gaps["surface"] < 1e-6, gaps
    assert gaps["world"] > 1e-2, gaps  # the frame matters


def test_mirror_symmetry_mirrors_the_frame() -> None:
    """A stroke mirrored across x on a model symmetric across x leaves it symmetric: the mirrored
    half took the reflection of the turned material (not a right-handed frame of its own)."""
    vertices, faces = icosphere(4)
    settings = _layered("surface")
    sculptor = Sculptor(vertices, faces, settings=settings)
    index = int(np.argmax(vertices @ np.array([0.6, 0.3, 0.7])))
    center = vertices[index]
    step = 0.03 * sculptor.model_size * np.array([0.2, 0.9, -0.1])
    brush = Brush("wrinkle", radius=0.07, symmetry="x")
    sculptor.apply_brush(brush, [BrushEvent(center + k * step, delta=step) for k in range(3)])
    flip = np.array([-1.0, 1.0, 1.0])
    # the vertex each vertex mirrors to
    order = np.lexsort(np.round(vertices * [-1, 1, 1], 9).T[::-1])
    mirror = np.empty_like(order)
    mirror[order] = np.lexsort(np.round(vertices, 9).T[::-1])
    assert np.abs(vertices[mirror] - vertices * flip).max() < 1e-9
    after = sculptor.vertices
    motion = np.linalg.norm(after - vertices, axis=1).max()
    assert motion > 0
    assert np.abs(after[mirror] - after * flip).max() < 1e-6 * motion


def test_surface_frame_rule() -> None:
    n = np.array([0.0, 0.0, 2.0])
    frame = surface_frame(n, np.array([1.0, 1.0, 5.0]))
    assert np.allclose(frame[:, 2], [0, 0, 1])
    assert np.allclose(frame[:, 0], np.array([1, 1, 0]) / np.sqrt(2))
    assert np.isclose(np.linalg.det(frame), 1.0)
    # no motion along the surface: the world axis least aligned with n, projected
    for motion in (None, np.array([0.0, 0.0, 3.0])):
        assert np.allclose(surface_frame(n, motion)[:, 0], [1, 0, 0])
    tilted = surface_frame(np.array([0.1, 0.9, 0.3]), None)
    assert tilted[:, 0] @ np.array([1.0, 0.0, 0.0]) > 0.9
    assert np.allclose(tilted.T @ tilted, np.eye(3))


@pytest.mark.parametrize("frame", ["surface", "world"])
def test_preview_and_pins_use_the_frame(frame: str) -> None:
    """The field preview and a pin drag turn with the model with the surface frame (and not
    with the world frame)."""
    from gogreen_core.sculpt.preview import field_preview

    vertices, faces = default_model(4)
    settings = _layered(frame)
    index = int(np.argmax(vertices @ np.array([0.3, 0.5, 0.8])))
    center = vertices[index]
    normal = center / np.linalg.norm(center)
    drag = np.cross(normal, [1.0, 0.0, 0.0])
    gaps = []
    results = []
    for turn in (np.eye(3), TURN):
        sculptor = Sculptor(vertices @ turn.T, faces, settings=settings)
        preview = field_preview(
            sculptor, Brush("grab", radius=0.06), turn @ center, turn @ normal, turn @ drag
        )
        assert preview is not None
        sculptor.add_constraint(turn @ center)
        sculptor.add_constraint(turn @ vertices[int(np.argmin(vertices @ normal))])
        moved = sculptor.drag_constraint(0, turn @ (0.02 * drag + 0.01 * normal))
        results.append((preview, moved))
    (p0, m0), (p1, m1) = results
    assert np.array_equal(p0.rows, p1.rows)
    gaps.append(np.abs(p0.velocity @ TURN.T - p1.velocity).max() / p0.motion.max())
    gaps.append(np.abs(m0 @ TURN.T - m1).max() / np.abs(m0).max())
    if frame == "surface":
        assert max(gaps) < 1e-6, gaps
    else:
        assert min(gaps) > 1e-3, gaps


def test_a_surface_frame_session_replays_bit_for_bit() -> None:
    """The frame comes from the mesh and the stroke's first event, so a replay takes the same
    frames: same vertices to the bit (and the session says "surface")."""
    import json

    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces, settings=_layered("world"))
    sculptor.change_settings(material=sculptor.settings.material, material_frame="surface")
    for kind, place in (("grab", 0), ("pinch", 40), ("wrinkle", 80)):
        center = vertices[place]
        normal = center / np.linalg.norm(center)
        tangent = np.cross(normal, [0.3, 1.0, 0.2])
        if kind == "pinch":
            event = BrushEvent(center, amount=0.05, axis=normal, direction=tangent)
        else:
            event = BrushEvent(center, delta=0.05 * (tangent + normal))
        sculptor.apply_brush(Brush(kind, radius=0.08), [event, event])
    session = json.loads(json.dumps(sculptor.session()))
    assert any(op.get("material_frame") == "surface" for op in session["operations"])
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
