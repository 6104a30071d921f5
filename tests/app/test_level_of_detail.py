"""Interaction frames from a lighter copy of a big mesh, the full mesh once it settles
(issue 36 item 3)."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
from gui_helpers import activate, center_of, shown_viewport
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest

import app.level_of_detail
from app.level_of_detail import LIGHT_FRAME_MS, _shares, cluster_decimation
from gogreen_core.mesh.shapes import icosphere


def test_cluster_decimation_keeps_the_shape_with_fewer_faces():
    vertices, faces = icosphere(5)  # 20,480 faces
    rows, light = cluster_decimation(vertices, faces, 2000)
    assert 1000 <= len(light) <= 3000
    assert len(np.unique(rows)) == len(rows)  # each copy vertex a different mesh vertex
    assert light.min() == 0 and light.max() == len(rows) - 1
    assert np.all(light[:, 0] != light[:, 1]) and np.all(light[:, 1] != light[:, 2])
    assert len(np.unique(np.sort(light, axis=1), axis=0)) == len(light)
    # on the sphere, facing out as the mesh's faces do
    a, b, c = (vertices[rows][light[:, k]] for k in range(3))
    outward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a + b + c)
    assert np.mean(outward > 0) > 0.99


@pytest.fixture
def big_viewport(qtbot, monkeypatch):
    """A viewport whose mesh counts as big (it gets an interaction copy)."""
    monkeypatch.setattr(app.level_of_detail, "LIGHT_MIN_FACES", 1000)
    vp = shown_viewport(qtbot)
    vertices, faces = icosphere(4)
    vp.set_mesh(vertices, faces)
    vp.render_now()
    assert vp.lod.light is not None
    return vp


def test_slow_frames_draw_the_copy_which_follows_the_moved_vertices(big_viewport):
    vp = big_viewport
    vp.lod.full_frame_ms = 0.5 * LIGHT_FRAME_MS  # a fast renderer: every frame in full
    vp.lod.interaction_frames()
    assert not vp.lod.shown
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    vp.lod.interaction_frames()
    assert vp.lod.shown and vp.lod.light.actor.GetVisibility() and not vp.mesh_actor.GetVisibility()
    vp.render_now()
    assert vp.lod.full_frame_ms == 5 * LIGHT_FRAME_MS  # a frame of the copy is not a full frame
    before = vp.surface.positions.copy()
    vertices = vp.surface.vertices
    moved = np.flatnonzero(vertices[:, 0] > 0.5)
    vertices[moved] *= 1.2
    vp.update_vertices(vertices, moved)
    # the copy shows the brush's effect; the full mesh's arrays wait for the settle
    light = vp.lod.light
    assert np.array_equal(light.index.vertices, vertices[light.rows])
    assert np.array_equal(vp.surface.positions, before)
    vp.lod.show_full()
    assert not vp.lod.shown and vp.mesh_actor.GetVisibility()
    assert not vp.lod.light.actor.GetVisibility()
    assert np.array_equal(vp.surface.vertices, vertices)
    assert np.array_equal(np.asarray(vp.mesh.points), vp.surface.positions)


def test_a_pick_during_copy_frames_sees_the_moved_surface(big_viewport):
    vp = big_viewport
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    vp.lod.interaction_frames()
    vertices = vp.surface.vertices * 1.5
    vp.update_vertices(vertices, np.arange(len(vertices)))
    pos = vp.rect().center()
    hit = vp.pick(pos.toPointF())
    assert hit is not None
    assert abs(np.linalg.norm(hit[0]) - 1.5) < 0.02  # on the grown sphere
    assert vp.lod.shown  # still drawing the copy


def test_mask_colours_reach_the_copy(big_viewport):
    vp = big_viewport
    mask = np.zeros(vp.mesh.n_points)
    mask[: len(mask) // 2] = 1.0
    vp.show_mask(mask)
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    vp.lod.interaction_frames()
    colors = np.asarray(vp.lod.light.polydata.point_data["Colors"])
    rows = vp.lod.light.rows[vp.lod.light.index.order]  # the copy's rows as mesh vertices
    dark = colors[:, 0] < 150
    assert np.array_equal(dark, mask[rows] > 0)


def test_mask_colours_reach_the_copy_drawn_while_a_dynamic_topology_stroke_runs(
    big_viewport, qtbot
):
    """Issue 34: the copy drawn during a dynamic-topology stroke (the mesh drawn flat, no index
    until the release) gets the mask tint, the colours then in the mesh's order; the release
    renumbers the index in place (the same one, on the background thread: it is not drawn)."""
    vp = big_viewport
    index, vertices, faces = vp.surface, vp.surface.vertices, vp._faces
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    vp.lod.interaction_frames()
    same = (faces, np.arange(len(vertices)), np.arange(len(faces)))  # a local change: none
    vp.set_mesh(vertices, faces.copy(), False, True, in_stroke=True, renumbering=same)
    assert vp.surface is None and vp.lod.shown
    mask = (vertices[:, 0] > 0.2).astype(float)
    vp.show_mask(mask)
    colors = np.asarray(vp.lod.light.polydata.point_data["Colors"])
    rows = vp.lod.light.rows[vp.lod.light.index.order]
    assert np.array_equal(colors[:, 0] < 150, mask[rows] > 0)
    vp.set_mesh(vertices, faces.copy(), reset_camera=False, background=True, renumbering=same)
    assert vp.surface_building
    qtbot.waitUntil(lambda: vp.surface is not None, timeout=60_000)
    assert vp.surface is index and vp.lod.light is not None


@pytest.mark.parametrize("fraction", [0.01, 0.5])
def test_renumberings_past_a_fraction_of_new_faces_start_a_sorted_build(
    big_viewport, qtbot, monkeypatch, fraction
):
    """Issue 34: new faces are appended to a renumbered index unsorted; once renumberings
    appended more than RESORT_FRACTION of the faces, a sorted build is made in the background
    while the renumbered index serves, and takes its place (Z-order leaves, a new build's
    picks); below it the renumbered index stays."""
    from gogreen_core.mesh.geometry import SurfaceIndex

    monkeypatch.setattr(app.level_of_detail, "RESORT_FRACTION", fraction)
    # the sorted build waits until the renumbered index was looked at (else, on a small mesh,
    # it may take over before the test first sees the renumbered one)
    gate, build = threading.Event(), app.level_of_detail._sorted_build
    held = lambda v, f: lambda task: (gate.wait(60), build(v, f)(task))[1]  # noqa: E731
    monkeypatch.setattr(app.level_of_detail, "_sorted_build", held)
    vp = big_viewport
    vertices, faces = vp.surface.vertices, vp._faces
    face_origin = np.arange(len(faces))
    face_origin[::20] = -1  # every 20th face "new": its old slot blanked, a slot written
    change = (faces, np.arange(len(vertices)), face_origin)
    vp.set_mesh(vertices, faces.copy(), reset_camera=False, background=True, renumbering=change)
    renumbered = vp.surface
    assert renumbered is not None and renumbered.unsorted == 2 * len(faces[::20])
    gate.set()
    if fraction > 0.05:
        qtbot.wait(300)
        assert vp.surface is renumbered and not vp.lod._resort.busy
        return
    qtbot.waitUntil(lambda: vp.surface is not renumbered, timeout=60_000)
    assert vp.surface.unsorted == 0 and vp.lod.light is not None
    _assert_index_of(vp.surface, vertices, faces, np.random.default_rng(5))
    fresh = SurfaceIndex(vertices, faces)
    assert np.array_equal(vp.surface.face_order, fresh.face_order)  # sorted again
    assert vp.mesh.n_cells == len(faces)


def test_a_stroke_on_a_slow_renderer_draws_the_copy_then_the_full_mesh(window, qtbot, monkeypatch):
    monkeypatch.setattr(app.level_of_detail, "LIGHT_MIN_FACES", 1000)
    activate(window, qtbot)
    vp = window.viewport
    sculptor = window.document.sculptor
    vp.set_mesh(sculptor.vertices, sculptor.faces)
    vp.render_now()
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    window.model.brush.kind = "grab"
    window.model.brush.radius = 0.2
    before = sculptor.vertices.copy()
    start = center_of(window)
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    shown_during = []
    for k in range(1, 8):
        QTest.mouseMove(vp, start + QPoint(6 * k, -4 * k))
        vp.flush_tools()
        shown_during.append(vp.lod.shown)
        vp.render_now()
        assert vp.lod.full_frame_ms == 5 * LIGHT_FRAME_MS  # the copy's frames are not full frames
    light = vp.lod.light.index.vertices
    assert np.array_equal(light, sculptor.vertices[vp.lod.light.rows])
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    assert all(shown_during)
    assert not vp.lod.shown and vp.mesh_actor.GetVisibility()
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)
    assert np.abs(sculptor.vertices - before).max() > 1e-3  # it sculpted


def test_software_opengl_draws_without_multisampling(big_viewport):
    """Mesa's llvmpipe (Xvfb, offscreen): 4 samples tripled a frame and took 340 MB at 1M."""
    vp = big_viewport
    assert vp.lod.software_gl is True
    assert vp.ren_win.GetMultiSamples() == 0


def test_a_thumbnail_from_the_copy_leaves_the_full_mesh_shown(big_viewport):
    vp = big_viewport
    frames = []
    vp.frame_rendered.connect(lambda _ms: frames.append(vp.lod.shown))
    image = vp.model_image(light=True)
    assert image.ndim == 3 and image.shape[2] == 3 and image.std() > 0
    assert frames and frames[0]  # drawn from the copy
    assert not vp.lod.shown and vp.mesh_actor.GetVisibility()
    assert not vp.lod.light.actor.GetVisibility()


def test_a_dynamic_topology_stroke_keeps_the_copy_and_renumbers_the_index(
    window, qtbot, monkeypatch, tmp_path
):
    """Issue 34: on a big mesh a dynamic-topology stroke draws the interaction copy all along
    (it follows the new vertices), and the release renumbers the index, no new build, to the
    normals, picks and faces of a new one; its undo and redo are renumbered too (the copy kept,
    no new build), all in place (the same index, its arrays VTK draws, the mesh drawn at
    once). The copy's new rows are found with each step, off the GUI thread."""
    from gogreen_core.mesh.geometry import SurfaceIndex

    builds = _dynamic_topology_window(window, qtbot, monkeypatch, tmp_path)
    monkeypatch.setattr(app.level_of_detail, "RESORT_FRACTION", 10.0)  # no sorted build
    vp, sculptor = window.viewport, window.document.sculptor
    vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS
    follows = []
    followed_rows = app.level_of_detail.LightMesh.followed_rows

    def spy(*args):  # where the copy's new rows are found: on the stroke's worker thread
        follows.append(threading.current_thread() is threading.main_thread())
        return followed_rows(*args)

    monkeypatch.setattr(app.level_of_detail.LightMesh, "followed_rows", spy)
    vertices, faces = sculptor.vertices.copy(), sculptor.faces.copy()
    before = vp.surface
    start = center_of(window)
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    shown_during = []
    for k in range(1, 6):
        QTest.mouseMove(vp, start + QPoint(8 * k, -6 * k))
        vp.flush_tools()
        qtbot.waitUntil(lambda: not vp.stroke_worker.running, timeout=60_000)
        shown_during.append(vp.lod.shown)
        light = vp.lod.light
        assert np.array_equal(light.index.vertices, sculptor.vertices[light.rows])
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    qtbot.waitUntil(lambda: vp.surface is not None and not vp.lod.shown, timeout=60_000)
    assert all(shown_during) and not builds and vp.surface is before
    assert follows and not any(follows)  # none on the GUI thread
    assert sculptor.faces.shape != faces.shape  # the stroke changed the topology
    fresh, index = SurfaceIndex(sculptor.vertices, sculptor.faces), vp.surface
    assert np.array_equal(index.normals[index.rank], fresh.normals[fresh.rank])
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)
    drawn = vp.mesh.regular_faces  # the mesh's faces, each once, as rows of the index
    drawn = drawn[(drawn[:, 0] != drawn[:, 1]) | (drawn[:, 1] != drawn[:, 2])]  # (no blanks)
    assert np.array_equal(
        np.sort(np.sort(index.order[drawn], axis=1), axis=0),
        np.sort(np.sort(sculptor.faces, axis=1), axis=0),
    )
    rng = np.random.default_rng(1)
    for _ in range(30):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.2 - origin
        got, expected = index.pick(origin, direction), fresh.pick(origin, direction)
        assert (got is None) == (expected is None)
        assert got is None or (got[0] == expected[0] and np.array_equal(got[1], expected[1]))
    stroke_vertices, stroke_faces = sculptor.vertices.copy(), sculptor.faces.copy()
    light = vp.lod.light
    for key, now in (
        (Qt.Key.Key_Z, (vertices, faces)),
        (Qt.Key.Key_Y, (stroke_vertices, stroke_faces)),
    ):
        vp.lod.full_frame_ms = 5 * LIGHT_FRAME_MS  # slow full frames
        QTest.keyClick(vp, key, Qt.KeyboardModifier.ControlModifier)  # undo, redo: renumbered too
        assert vp.surface is before and not vp.surface_building  # in place, at once
        assert not vp.lod.shown and vp.mesh_actor.GetVisibility()
        assert _shares(vp.mesh, before)  # VTK draws the index's arrays
        assert np.array_equal(sculptor.faces, now[1]) and np.array_equal(sculptor.vertices, now[0])
        assert np.array_equal(vp.shown_vertices(), now[0])
        assert vp.mesh.n_cells == len(before.faces) and not builds and vp.lod.light is light
        fresh, index = SurfaceIndex(*now), vp.surface
        assert np.array_equal(index.normals[index.rank], fresh.normals[fresh.rank])
        assert np.array_equal(light.index.vertices, sculptor.vertices[light.rows])


def test_an_undo_while_the_release_renumbering_waits_behind_other_work_does_not_freeze(
    window, qtbot, monkeypatch, tmp_path
):
    """A stroke's release renumbers the index in place on the one background thread; an undo
    pressed while that job still waits behind other work there (a homogenization, the kernels'
    warm-up) drops it (the index untouched) and builds anew instead of blocking the GUI until
    that work ends (pressed while it runs, it waits for it: the test above)."""
    from app.background import BackgroundRunner

    builds = _dynamic_topology_window(window, qtbot, monkeypatch, tmp_path)
    vp, sculptor = window.viewport, window.document.sculptor
    vertices, faces = sculptor.vertices.copy(), sculptor.faces.copy()
    start = center_of(window)
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    for k in range(1, 4):
        QTest.mouseMove(vp, start + QPoint(8 * k, -6 * k))
        vp.flush_tools()
        qtbot.waitUntil(lambda: not vp.stroke_worker.running, timeout=60_000)
    gate, blocker = threading.Event(), BackgroundRunner()
    blocker.submit(lambda _task: gate.wait(20))  # other work ahead on the worker thread
    try:
        QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
        qtbot.waitUntil(lambda: vp.surface_building, timeout=60_000)  # the renumbering queued
        assert sculptor.faces.shape != faces.shape and not builds
        began = time.perf_counter()
        QTest.keyClick(vp, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
        waited = time.perf_counter() - began
    finally:
        gate.set()
    assert waited < 5.0  # (it waited for the blocker's 20 s before)
    assert np.array_equal(sculptor.faces, faces) and np.array_equal(sculptor.vertices, vertices)
    qtbot.waitUntil(lambda: vp.surface is not None, timeout=60_000)
    assert builds  # the undo's faces indexed anew: the dropped renumbering never ran
    _assert_index_of(vp.surface, vertices, faces, np.random.default_rng(3))


def _dynamic_topology_window(window, qtbot, monkeypatch, tmp_path):
    """The window on a "big" copy of its model (an interaction copy, a background index),
    dynamic topology on, a grab brush; new index builds are counted in the list returned."""
    import app.mesh_display
    from gogreen_core.mesh.mesh_io import MeshData, save_mesh

    monkeypatch.setattr(app.level_of_detail, "LIGHT_MIN_FACES", 1000)
    monkeypatch.setattr(app.mesh_display, "BACKGROUND_INDEX_FACES", 1000)
    activate(window, qtbot)
    sculptor = window.document.sculptor
    path = str(tmp_path / "model.ply")
    save_mesh(MeshData(sculptor.vertices, sculptor.faces), path)
    assert window.files.open_file(path)
    qtbot.waitUntil(lambda: window.viewport.surface is not None, timeout=60_000)
    window.viewport.render_now()
    builds: list[int] = []
    build = app.level_of_detail.indexed
    monkeypatch.setattr(app.level_of_detail, "indexed", lambda *a: builds.append(1) or build(*a))
    window.model.dynamic_topology = True
    window.model.detail_size = 0.004
    window.model.brush.kind = "grab"
    window.model.brush.radius = 0.2
    return builds


def _assert_index_of(index, vertices, faces, rng):
    """``index`` has the positions, normals (bit for bit), face normals, drawn faces and picks
    of a new build on the mesh ``vertices``, ``faces``."""
    from gogreen_core.mesh.geometry import SurfaceIndex

    fresh = SurfaceIndex(vertices, faces)
    assert np.array_equal(index.order[index.rank], np.arange(len(vertices)))
    assert np.array_equal(index.positions[index.rank], vertices)
    live = np.flatnonzero(index.face_order >= 0)  # (not the blanked slots)
    drawn = np.sort(np.sort(index.order[index.faces[live]], axis=1), axis=0)
    assert np.array_equal(drawn, np.sort(np.sort(faces, axis=1), axis=0))
    assert np.array_equal(index.normals[index.rank], fresh.normals[fresh.rank])
    assert np.array_equal(index._face_normals[live[np.argsort(index.face_order[live])]],
                          fresh._face_normals[np.argsort(fresh.face_order)])  # fmt: skip
    for _ in range(40):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.3 - origin
        got, expected = index.pick(origin, direction), fresh.pick(origin, direction)
        assert (got is None) == (expected is None)
        if got is not None:
            assert got[0] == expected[0]
            assert np.array_equal(got[1], expected[1])


def test_renumbered_index_after_local_remeshes_undo_and_redo_equals_a_new_build():
    """Issue 34: random local remeshes (vertices split, collapsed, moved), then their undo
    and redo steps, renumber the index in place (:meth:`SurfaceIndex.renumber`: the kept rows
    in their slots, the new ones in free slots or after) to the normals (bit for bit), picks
    and drawn faces of a new index on the same mesh; one brush move after it too."""
    from app.level_of_detail import edit_renumbering
    from gogreen_core.mesh.geometry import SurfaceIndex
    from gogreen_core.mesh.mesh_state import MeshSnapshot, MeshState, topology_edit
    from gogreen_core.mesh.remesh import remesh
    from gogreen_core.mesh.shapes import default_model

    vertices, faces = default_model(4)
    state = MeshState(vertices, faces)
    index = SurfaceIndex(vertices, faces)
    rng = np.random.default_rng(7)
    removed = added = 0
    median = np.median(np.linalg.norm(vertices[faces[:, 0]] - vertices[faces[:, 1]], axis=1))
    steps = []
    for _ in range(4):
        vertices, faces = state.vertices, state.faces
        center = vertices[rng.integers(len(vertices))]
        near = np.linalg.norm(vertices - center, axis=1)
        moved = vertices + 0.01 * rng.normal(size=vertices.shape) * (near < 0.3)[:, None]
        done = remesh(moved, faces, near < 0.35, median * rng.choice([0.5, 2.0]), iterations=2)
        removed += int((done.kept < 0).sum())
        added += len(done.vertices) - int((done.kept >= 0).sum())
        origin = np.full(len(done.vertices), -1)
        origin[: np.count_nonzero(done.kept >= 0)] = np.flatnonzero(done.kept >= 0)
        face_origin = np.full(len(done.faces), -1)
        face_origin[: np.count_nonzero(done.kept_faces)] = np.flatnonzero(done.kept_faces)
        before = MeshSnapshot(vertices, faces, state.mask)
        after = MeshSnapshot(done.vertices, done.faces, np.zeros(len(done.vertices)))
        steps.append(topology_edit(before, after, origin, face_origin))
        slots = index.rank.copy()
        index.renumber(done.vertices, done.faces, origin, face_origin)
        state.adopt(after)
        n = np.count_nonzero(origin >= 0)  # the kept vertices keep their slots
        assert np.array_equal(index.rank[:n], slots[origin[:n]])
        _assert_index_of(index, done.vertices, done.faces, rng)
    assert removed > 0 and added > 0
    for side in [back for back, _ in reversed(steps)] + [forth for _, forth in steps]:
        change = edit_renumbering(side, state.faces)  # an undo or a redo: how it renumbers
        assert edit_renumbering(side, state.faces[1:]) is None  # another mesh's
        state.adopt(side)
        index.renumber(state.vertices, state.faces, change[1], change[2])
        _assert_index_of(index, state.vertices, state.faces, rng)
    moved = state.vertices.copy()
    rows = np.flatnonzero(np.linalg.norm(moved - moved[0], axis=1) < 0.3)
    moved[rows] += 0.02
    index.update(moved, rows)
    _assert_index_of(index, moved, state.faces, rng)


def test_a_copy_vertex_collapsed_away_follows_a_neighbour_on_its_side_of_a_pull():
    """Issue 34: after a dynamic-topology pull, a copy vertex the remesh collapsed away takes
    a kept neighbour from before the stroke; the new corner nearest to where the copy drew it
    could be across the pull's fold, and the copy showed faces turned inside out (46 on this
    pull, none before it; 3 now)."""
    from scipy.spatial import cKDTree

    from gogreen_core import Brush, BrushEvent, EngineSettings, Sculptor
    from gogreen_core.mesh.geometry import SurfaceIndex, vertex_normals
    from gogreen_core.mesh.shapes import default_model

    vertices, faces = default_model()
    sculptor = Sculptor(vertices, faces, settings=EngineSettings(dynamic_topology=True))
    light = app.level_of_detail.LightMesh(vertices, faces, target_faces=len(faces) // 10)
    top = int(np.argmax(vertices @ [0.1, 0.2, 1.0]))
    normal = vertex_normals(vertices, faces)[top]
    centre = vertices[top].copy()
    sculptor.begin_stroke(Brush("grab", radius=0.03))
    for k in range(12):
        step = 0.015 * sculptor.model_size * (normal + np.array([0.5 * (k % 3 == 0), 0, 0]))
        sculptor.stroke_event(BrushEvent(centre, step))
        centre = centre + step
    new_vertices, new_faces = sculptor.vertices, sculptor.faces
    change = sculptor.remesher.mesh.renumbering
    light.follow(new_vertices, new_faces, change, SurfaceIndex(vertices, faces))
    assert np.all(light.rows >= 0)
    copy = new_vertices[light.rows][light.index.order][light.index.faces]
    face_normals = np.cross(copy[:, 1] - copy[:, 0], copy[:, 2] - copy[:, 0])
    nearest = cKDTree(new_vertices).query(copy.mean(axis=1))[1]
    facing = np.einsum("ij,ij->i", face_normals, vertex_normals(new_vertices, new_faces)[nearest])
    turned = facing < -0.2 * np.linalg.norm(face_normals, axis=1)
    assert np.count_nonzero(turned) <= 10
