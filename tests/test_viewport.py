"""The viewport alone (no main window): incremental normals, ray picking, the cursor overlay."""

import numpy as np
import pytest
import vtk
from PySide6.QtCore import QPointF

from app.viewport import SculptViewport
from gogreen_core.geometry import vertex_normals
from gogreen_core.shapes import icosphere


@pytest.fixture
def viewport(qtbot):
    vp = SculptViewport()
    qtbot.addWidget(vp)
    vp.resize(500, 400)
    vp.show()
    qtbot.waitExposed(vp)
    vertices, faces = icosphere(3)
    vertices = vertices * (1.0 + 0.1 * np.sin(5 * vertices[:, :1]))  # not a plain sphere
    vp.set_mesh(vertices, faces)
    vp.render_now()
    return vp


def old_pick(vp: SculptViewport, pos: QPointF):
    """The picker the viewport used before: a VTK cell picker over the whole actor."""
    picker = vtk.vtkCellPicker()
    picker.SetTolerance(1e-4)
    picker.AddPickList(vp.mesh_actor)
    picker.PickFromListOn()
    x, y = vp._display(pos)
    if not picker.Pick(x, y, 0, vp.renderer):
        return None
    return np.array(picker.GetPickPosition()), np.array(picker.GetPickNormal())


def test_normals_after_a_local_change_equal_a_full_recompute(viewport):
    vertices = viewport.mesh.points.copy()
    faces = viewport._faces
    moved = np.flatnonzero(vertices[:, 0] > 0.6)
    assert 0 < len(moved) < len(vertices) // 4
    vertices[moved] += np.array([0.05, 0.02, -0.03]) * vertices[moved, :1]
    viewport.update_vertices(vertices, moved)
    assert np.array_equal(viewport.mesh.points, vertices)
    assert np.array_equal(viewport.mesh.point_data["Normals"], vertex_normals(vertices, faces))
    # without indices (undo): the rows that differ are found
    again = vertices.copy()
    again[:10] *= 1.1
    viewport.update_vertices(again)
    assert np.array_equal(viewport.mesh.point_data["Normals"], vertex_normals(again, faces))


def test_update_keeps_the_actor_and_its_arrays(viewport):
    actor, points = viewport.mesh_actor, viewport.mesh.GetPoints().GetData()
    normals = viewport.mesh.GetPointData().GetNormals()
    stamp = points.GetMTime()
    vertices = viewport.mesh.points.copy()
    vertices[:5] += 0.01
    viewport.update_vertices(vertices, np.arange(5))
    assert viewport.mesh_actor is actor
    assert viewport.mesh.GetPoints().GetData() is points
    assert viewport.mesh.GetPointData().GetNormals() is normals
    assert points.GetMTime() > stamp


def test_pick_matches_the_vtk_cell_picker(viewport):
    w, h = viewport.width(), viewport.height()
    hits = 0
    for fx in np.linspace(0.2, 0.8, 7):
        for fy in np.linspace(0.2, 0.8, 7):
            pos = QPointF(fx * w, fy * h)
            got, expected = viewport.pick(pos), old_pick(viewport, pos)
            assert (got is None) == (expected is None), pos
            if got is None:
                continue
            hits += 1
            # VTK's cell picker works to its tolerance (1e-4 of the view): same point to that
            np.testing.assert_allclose(got[0], expected[0], atol=5e-4)
            np.testing.assert_allclose(got[1], expected[1], atol=5e-3)
    assert hits > 10
    assert viewport.pick(QPointF(2, 2)) is None  # the background


def test_pick_follows_moved_vertices(viewport):
    pos = QPointF(viewport.width() / 2, viewport.height() / 2)
    before = viewport.pick(pos)[0]
    vertices = viewport.mesh.points.copy() * 1.2  # every vertex, towards the camera
    viewport.update_vertices(vertices)
    viewport.render_now()
    after, expected = viewport.pick(pos), old_pick(viewport, pos)
    np.testing.assert_allclose(after[0], expected[0], atol=5e-4)
    assert not np.allclose(after[0], before)


def test_cursor_overlay_is_2d_sized_by_projection_and_follows_the_radius(viewport):
    from gogreen_core.tools import CursorState

    pos = QPointF(viewport.width() / 2, viewport.height() / 2)
    point, normal = viewport.pick(pos)
    profile = np.linspace(1.0, 0.0, 16)
    viewport.show_cursor(CursorState(point, normal, 0.1, 3.0, profile))
    viewport.render_now()
    overlay = viewport.cursor_overlay
    assert viewport.cursor_visible and overlay.screen is not None
    (x, y), eps_px, outer_px = overlay.screen
    # centred on the picked point's screen position (display y is up)
    assert abs(x - pos.x()) < 1.5 and abs(y - (viewport.height() - 1 - pos.y())) < 1.5
    assert outer_px == pytest.approx(3.0 * eps_px)
    # the world radius projected: a camera-perpendicular offset of 0.1 lands eps_px away
    camera = viewport.renderer.GetActiveCamera()
    up = np.array(camera.GetViewUp())
    viewport.renderer.SetWorldPoint(*(point + 0.1 * up), 1.0)
    viewport.renderer.WorldToDisplay()
    top = np.array(viewport.renderer.GetDisplayPoint()[:2])
    assert np.hypot(*(top - (x, y))) == pytest.approx(eps_px, rel=0.1)  # perspective
    # 2D actors: drawn over the scene, never depth-tested against the surface
    assert overlay._ring.actor.IsA("vtkActor2D") and overlay._ring.actor.GetVisibility()
    # a new radius shows at once, without a mouse move
    viewport.show_cursor(CursorState(point, normal, 0.2, 3.0, profile))
    viewport.render_now()
    assert overlay.screen[1] == pytest.approx(2 * eps_px, rel=0.05)
    viewport.show_cursor(None)
    viewport.render_now()
    assert not viewport.cursor_visible and not overlay._ring.actor.GetVisibility()
