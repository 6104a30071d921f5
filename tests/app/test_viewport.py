"""The viewport alone (no main window): incremental normals, ray picking, the cursor overlay."""

import gc
import threading

import numpy as np
import pytest
import vtk
from gui_helpers import send, shown_viewport
from PySide6.QtCore import QPointF, QTimer
from PySide6.QtGui import QMouseEvent, QSurface

from app.viewport import SculptViewport
from gogreen_core.mesh.geometry import SurfaceIndex, vertex_normals
from gogreen_core.mesh.shapes import icosphere


@pytest.fixture
def viewport(qtbot):
    vp = shown_viewport(qtbot)
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


def shown_normals(vp: SculptViewport) -> np.ndarray:
    """The normals VTK draws, in the mesh's vertex order."""
    return np.asarray(vp.mesh.point_data["Normals"])[vp.surface.rank]


def full_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The normals of ``vertices`` recomputed over the whole mesh by the same code (a new
    index), checked against numpy's :func:`vertex_normals` to float32 rounding."""
    fresh = SurfaceIndex(vertices, faces)
    normals = fresh.normals[fresh.rank]
    np.testing.assert_allclose(normals, vertex_normals(vertices, faces), rtol=0, atol=2e-6)
    return normals


def test_normals_after_a_local_change_equal_a_full_recompute(viewport):
    vertices = viewport.shown_vertices()
    faces = viewport._faces
    moved = np.flatnonzero(vertices[:, 0] > 0.6)
    assert 0 < len(moved) < len(vertices) // 4
    vertices[moved] += np.array([0.05, 0.02, -0.03]) * vertices[moved, :1]
    viewport.update_vertices(vertices, moved)
    assert np.array_equal(viewport.shown_vertices(), vertices)
    # the arrays VTK draws are the index's own (no copy per event)
    assert np.shares_memory(viewport.mesh.points, viewport.surface.positions)
    assert np.array_equal(np.asarray(viewport.mesh.points)[viewport.surface.rank], vertices)
    assert np.array_equal(shown_normals(viewport), full_normals(vertices, faces))
    # without indices (undo): the rows that differ are found
    again = vertices.copy()
    again[:10] *= 1.1
    viewport.update_vertices(again)
    assert np.array_equal(viewport.shown_vertices(), again)
    assert np.array_equal(shown_normals(viewport), full_normals(again, faces))


def test_update_keeps_the_actor_and_its_arrays(viewport):
    actor, points = viewport.mesh_actor, viewport.mesh.GetPoints().GetData()
    normals = viewport.mesh.GetPointData().GetNormals()
    stamp = points.GetMTime()
    vertices = viewport.shown_vertices()
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
    vertices = viewport.shown_vertices() * 1.2  # every vertex, towards the camera
    viewport.update_vertices(vertices)
    viewport.render_now()
    after, expected = viewport.pick(pos), old_pick(viewport, pos)
    np.testing.assert_allclose(after[0], expected[0], atol=5e-4)
    assert not np.allclose(after[0], before)


def test_cursor_overlay_is_2d_sized_by_projection_and_follows_the_radius(viewport):
    from gogreen_core.interaction.tools import CursorState

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


class GatedIndex:
    """A SurfaceIndex whose build waits, after its first stages, until the test opens the
    gate: the build is certainly still running while the test looks at the window."""

    def __init__(self, monkeypatch):
        import app.level_of_detail as viewport_module  # where the build runs

        self.gate = threading.Event()
        self.started = threading.Event()
        real = viewport_module.SurfaceIndex
        gated = self

        def build(vertices, faces, progress=None):
            def report(fraction):
                if progress is not None:
                    progress(fraction)
                background = threading.current_thread() is not threading.main_thread()
                if background and fraction >= 0.4 and not gated.gate.is_set():
                    gated.started.set()
                    assert gated.gate.wait(30), "the test never opened the gate"

            return real(vertices, faces, report)

        monkeypatch.setattr(viewport_module, "SurfaceIndex", build)


def test_background_index_build_keeps_the_view_usable_and_loses_nothing(qtbot, monkeypatch):
    gated = GatedIndex(monkeypatch)
    vp = shown_viewport(qtbot)
    vertices, faces = icosphere(3)
    progress = []
    vp.surface_progress.connect(progress.append)
    vp.set_mesh(vertices, faces, background=True)
    assert gated.started.wait(30)
    assert vp.surface_building and vp.surface is None
    assert vp.mesh.n_points == len(vertices)  # shown (flat) while the index builds
    vp.render_now()
    center = QPointF(vp.width() / 2, vp.height() / 2)
    assert vp.pick(center) is None
    pressed = []
    vp.pointer_pressed.connect(pressed.append)
    with qtbot.waitSignal(vp.surface_pending, timeout=1000):
        send(vp, QMouseEvent.Type.MouseButtonPress, center)
    assert not pressed and not vp.in_stroke  # no stroke starts without a surface to pick
    # vertices moved meanwhile (undo, a script) are drawn, and the index catches up
    moved = vertices * 1.1
    vp.update_vertices(moved)
    assert np.array_equal(vp.shown_vertices(), moved)
    with qtbot.waitSignal(vp.surface_ready, timeout=30_000):
        gated.gate.set()
    assert not vp.surface_building and progress and progress[-1] == 1.0
    assert np.array_equal(vp.shown_vertices(), moved)
    assert np.array_equal(shown_normals(vp), full_normals(moved, faces))
    vp.render_now()
    assert vp.pick(center) is not None
    with qtbot.waitSignal(vp.pointer_pressed, timeout=1000):
        send(vp, QMouseEvent.Type.MouseButtonPress, center)


def test_a_newer_mesh_supersedes_a_background_build(qtbot, monkeypatch):
    gated = GatedIndex(monkeypatch)
    vp = shown_viewport(qtbot)
    big, big_faces = icosphere(3)
    vp.set_mesh(big, big_faces, background=True)
    assert gated.started.wait(30)
    small, small_faces = icosphere(1)
    vp.set_mesh(small, small_faces, background=False)
    assert not vp.surface_building and vp.surface is not None
    ready = []
    vp.surface_ready.connect(lambda: ready.append(True))
    gated.gate.set()
    vp.wait_for_surface(30_000)
    qtbot.wait(50)
    assert not ready  # the old build was dropped
    assert vp.mesh.n_points == len(small)
    assert np.array_equal(vp.shown_vertices(), small)


def test_opening_a_big_mesh_does_not_block_the_event_loop(window, qtbot, monkeypatch, tmp_path):
    """File → Open of a mesh whose index builds in the background: the window returns to
    its event loop at once, a press says why nothing happens, and the index becomes ready."""
    import app.mesh_display as viewport_module

    gated = GatedIndex(monkeypatch)
    monkeypatch.setattr(viewport_module, "BACKGROUND_INDEX_FACES", 1)  # a small "big" mesh
    vertices, faces = icosphere(3)
    path = tmp_path / "big.obj"
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    assert window.files.open_file(str(path))
    vp = window.viewport
    assert gated.started.wait(30) and vp.surface_building
    assert window.surface_progress.isVisible()
    # the event loop turns (timers fire, paints happen) while the index builds
    ticks = []
    QTimer.singleShot(0, lambda: ticks.append(1))
    qtbot.waitUntil(lambda: bool(ticks), timeout=2000)
    before = window.document.sculptor.vertices.copy()
    send(vp, QMouseEvent.Type.MouseButtonPress, QPointF(vp.width() / 2, vp.height() / 2))
    assert "being prepared" in window.message_label.text()
    assert np.array_equal(window.document.sculptor.vertices, before)
    with qtbot.waitSignal(vp.surface_ready, timeout=30_000):
        gated.gate.set()
    assert not window.surface_progress.isVisible()
    assert "ready to sculpt" in window.message_label.text()
    assert vp.surface is not None and np.array_equal(vp.shown_vertices(), before)
    vp.render_now()
    assert vp.pick(QPointF(vp.width() / 2, vp.height() / 2)) is not None


def _surface_wrappers() -> int:
    """Python wrappers of a bare QSurface alive now (PySide cannot tell when Qt deletes one)."""
    return sum(type(o) is QSurface for o in gc.get_objects())


def test_a_closed_viewport_keeps_no_wrapper_of_its_gl_surface(viewport):
    """The GL surface Qt deletes with the widget is no QObject: a wrapper of it kept past the
    close stays registered at that address, and PySide handed it back for a new object there
    (a field's line edit came back as a QSurface)."""
    before = _surface_wrappers()
    assert before >= 1  # the shown viewport's, which pyvistaqt keeps for its context
    viewport.close()
    assert _surface_wrappers() == before - 1
