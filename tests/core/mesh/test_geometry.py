"""Incremental vertex normals and picking of the SurfaceIndex (gogreen_core.mesh.geometry)."""

from __future__ import annotations

import numpy as np
import pytest

from gogreen_core._compiled import forced
from gogreen_core.mesh.geometry import (
    LEAF_SIZE,
    PARALLEL_VERTICES,
    SurfaceIndex,
    vertex_normals,
)
from gogreen_core.mesh.shapes import default_model, icosphere


@pytest.fixture(autouse=True)
def compiled():
    """The compiled functions (their bits are the ones these tests pin; the NumPy twins that
    serve until they are ready are held to them in ``test_geometry_numpy.py``)."""
    with forced("unrolled"):
        yield


@pytest.fixture(scope="module")
def pebble():
    return default_model(4)


def assert_normals_of(index, vertices, faces):
    """The index's normals are, bit for bit, those of a new index built on ``vertices``
    (the same code on the whole mesh), and numpy's :func:`vertex_normals` to the float32
    rounding of the face normals."""
    fresh = SurfaceIndex(vertices, faces)
    shown = index.normals[index.rank]
    assert np.array_equal(shown, fresh.normals[fresh.rank])
    # float32 face normals (relative rounding 2**-24 each): a vertex normal is off by at most
    # about 2**-24 · Σ|face normal| / |Σ face normal| (large where the faces nearly cancel)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    lengths = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    spread = np.bincount(faces.ravel(), np.repeat(lengths, 3), minlength=len(vertices))
    total = np.zeros((len(vertices), 3))
    np.add.at(total, faces.ravel(), np.repeat(np.cross(b - a, c - a), 3, axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = 4 * 2.0**-24 * np.nan_to_num(spread / np.linalg.norm(total, axis=1))
    error = np.abs(shown - vertex_normals(vertices, faces)).max(axis=1)
    assert np.all(error <= bound + 1e-15)


def brush_move(vertices, center_index, radius, seed=0):
    """Vertices moved randomly within ``radius`` of one vertex, and their indices."""
    rng = np.random.default_rng(seed)
    changed = np.flatnonzero(np.linalg.norm(vertices - vertices[center_index], axis=1) < radius)
    moved = vertices.copy()
    moved[changed] += 0.02 * rng.normal(size=(len(changed), 3))
    return moved, changed


def test_index_arrays_are_the_mesh_in_its_own_order(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    assert np.array_equal(index.order[index.rank], np.arange(len(vertices)))
    assert np.array_equal(index.positions, vertices[index.order])
    assert np.array_equal(index.vertices, vertices)
    assert np.array_equal(np.sort(index.face_order), np.arange(len(faces)))
    assert np.array_equal(index.order[index.faces], faces[index.face_order])  # corner order kept


def test_incremental_normals_equal_full_recompute_bit_for_bit(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    assert_normals_of(index, vertices, faces)
    before = index.normals[index.rank]
    moved, changed = brush_move(vertices, 5, 0.6)
    count = index.update(moved, changed)
    # every row: the recomputed ones and the ones left alone
    assert_normals_of(index, moved, faces)
    assert np.array_equal(index.vertices, moved)
    ring = np.unique(faces[np.any(np.isin(faces, changed), axis=1)])
    assert count == len(ring) > len(changed)
    untouched = np.setdiff1d(np.arange(len(vertices)), ring)
    assert np.array_equal(index.normals[index.rank][untouched], before[untouched])
    assert not np.array_equal(index.normals[index.rank][ring], before[ring])
    # a second event elsewhere, from the updated state
    moved2, changed2 = brush_move(moved, 40, 0.5, seed=1)
    index.update(moved2, changed2)
    assert_normals_of(index, moved2, faces)
    assert index.changed_rows(moved2).size == 0  # what an undo compares with
    expected = np.flatnonzero(np.any(moved != moved2, axis=1))
    assert len(expected) and np.array_equal(index.changed_rows(moved), expected)
    # rows outside ``changed`` are not read: the index keeps the positions it was given
    stale = moved2.copy()
    stale[np.setdiff1d(np.arange(len(stale)), changed2)] = np.nan
    index.update(stale, changed2)
    assert_normals_of(index, moved2, faces)


def test_updates_from_many_threads_chunks_match_a_single_thread(pebble):
    """The passes deal chunks to the threads: a brush region spanning many chunks (every
    vertex of a bigger mesh) gives the same bits as a fresh build."""
    vertices, faces = icosphere(6)  # 40,962 vertices: several chunks per thread
    index = SurfaceIndex(vertices, faces)
    moved, changed = brush_move(vertices, 0, 1.6, seed=2)
    assert len(changed) >= PARALLEL_VERTICES  # the update runs on all threads
    index.update(moved, changed)
    assert_normals_of(index, moved, faces)
    # a small update afterwards runs on the calling thread alone: same bits
    moved2, changed2 = brush_move(moved, 7, 0.05, seed=3)
    assert 0 < len(changed2) < PARALLEL_VERTICES
    index.update(moved2, changed2)
    assert_normals_of(index, moved2, faces)


def test_isolated_vertex_normal_matches_full():
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]])
    faces = np.array([[0, 1, 2]])
    index = SurfaceIndex(np.zeros((4, 3)), faces)
    index.update(vertices, np.arange(4))
    assert_normals_of(index, vertices, faces)
    assert np.array_equal(index.normals[index.rank[3]], [0.0, 0.0, 1.0])


def test_build_reports_progress_and_stops_when_the_callback_raises(pebble):
    vertices, faces = pebble
    seen = []
    SurfaceIndex(vertices, faces, progress=seen.append)
    assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) >= 3

    class Stop(Exception):
        pass

    def stop(fraction):
        if fraction > 0.3:
            raise Stop

    with pytest.raises(Stop):
        SurfaceIndex(vertices, faces, progress=stop)


def test_bad_meshes_and_updates_are_refused(pebble):
    with pytest.raises(ValueError, match="shape"):
        SurfaceIndex(np.zeros((3, 3)), np.array([0, 1, 2]))
    with pytest.raises(ValueError, match="index vertices"):
        SurfaceIndex(np.zeros((3, 3)), np.array([[0, 1, 3]]))
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    with pytest.raises(ValueError, match="changed must index"):
        index.update(vertices, np.array([len(vertices)]))
    with pytest.raises(ValueError, match="shape"):
        index.update(vertices[:-1], np.array([0]))


def brute_force_pick(vertices, faces, origin, direction):
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    e1, e2 = b - a, c - a
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(all="ignore"):
        inv = 1.0 / det
        s = origin - a
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ direction) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
    ok = (det != 0) & (u >= 0) & (u <= 1) & (v >= 0) & (u + v <= 1) & (t >= 0)
    if not ok.any():
        return None
    best = np.flatnonzero(ok)[np.argmin(t[ok])]
    return best, origin + t[best] * direction


def test_pick_matches_brute_force_after_the_mesh_moves(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    moved, changed = brush_move(vertices, 5, 0.8)
    moved[changed] += 0.3 * (moved[changed] - vertices[5])  # far beyond the old boxes
    index.pick(vertices[5] + 3.0, -vertices[5])  # boxes fitted, then moved: stale
    index.update(moved, changed)
    # boxes are refit lazily: not by the update, by the next pick
    assert index._stale_boxes
    rng = np.random.default_rng(3)
    hits = 0
    for _ in range(100):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.3 - origin
        got = index.pick(origin, direction)
        assert not index._stale_boxes
        expected = brute_force_pick(moved, faces, origin, direction)
        assert (got is None) == (expected is None)
        if got is not None:
            hits += 1
            assert got[0] == expected[0]
            assert np.allclose(got[1], expected[1], atol=1e-12)
    assert hits > 50
    # several updates between two picks (a stroke), the last one back home
    index.update(vertices, changed)
    moved2, changed2 = brush_move(vertices, 30, 0.7, seed=4)
    index.update(moved2, changed2)
    for _ in range(50):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.3 - origin
        got = index.pick(origin, direction)
        expected = brute_force_pick(moved2, faces, origin, direction)
        assert (got is None) == (expected is None)
        if got is not None:
            assert got[0] == expected[0]
            assert np.allclose(got[1], expected[1], atol=1e-12)
    boxes = index._boxes
    corners = index.positions[index.faces]  # (M, 3, 3) in leaf order
    leaf = np.arange(len(index.faces)) // LEAF_SIZE
    assert np.all(boxes[leaf, :3] <= corners.min(axis=1))
    assert np.all(boxes[leaf, 3:] >= corners.max(axis=1))


def test_pick_misses_and_bad_rays(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    assert index.pick(np.array([0.0, 0.0, 10.0]), np.array([0.0, 0.0, 1.0])) is None
    with pytest.raises(ValueError, match="nonzero"):
        index.pick(np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="finite"):
        index.pick(np.array([np.nan, 0, 0]), np.ones(3))


def local_remesh(vertices, faces, center, detail, seed):
    """A local remesh around vertex ``center`` (moved a little first) and how it renumbered
    the mesh: (vertices, faces, origin, face_origin), the kept rows first, in order."""
    from gogreen_core.mesh.remesh import remesh

    near = np.linalg.norm(vertices - vertices[center], axis=1)
    rng = np.random.default_rng(seed)
    moved = vertices + 0.01 * rng.normal(size=3) * (near < 0.3)[:, None]
    done = remesh(moved, faces, near < 0.35, detail, iterations=2)
    origin = np.full(len(done.vertices), -1)
    origin[: np.count_nonzero(done.kept >= 0)] = np.flatnonzero(done.kept >= 0)
    face_origin = np.full(len(done.faces), -1)
    face_origin[: np.count_nonzero(done.kept_faces)] = np.flatnonzero(done.kept_faces)
    return done.vertices, done.faces, origin, face_origin


def inverted(origin, n_before):
    """The renumbering back (an undo): each row before's row now (-1: removed by it)."""
    back = np.full(n_before, -1)
    kept = np.flatnonzero(origin >= 0)
    back[origin[kept]] = kept
    return back


def assert_same_as_new_build(index, vertices, faces, seed=5):
    """Normals bit for bit, faces drawn (blanked slots aside: one corner thrice), picks."""
    assert_normals_of(index, vertices, faces)
    assert np.array_equal(index.vertices, vertices)
    live = index.face_order >= 0
    blank = index.faces[~live]
    assert np.all((blank[:, 0] == blank[:, 1]) & (blank[:, 1] == blank[:, 2]))
    assert np.array_equal(np.sort(index.face_order[live]), np.arange(len(faces)))
    assert np.array_equal(index.order[index.faces[live]], faces[index.face_order[live]])
    assert np.array_equal(index.order[index.rank], np.arange(len(vertices)))
    fresh = SurfaceIndex(vertices, faces)
    rng = np.random.default_rng(seed)
    for _ in range(40):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.3 - origin
        got, expected = index.pick(origin, direction), fresh.pick(origin, direction)
        assert (got is None) == (expected is None)
        assert got is None or (got[0] == expected[0] and np.array_equal(got[1], expected[1]))


@pytest.mark.parametrize("mode", ["unrolled", "numpy"])
def test_an_index_renumbered_in_place_over_local_changes_equals_a_new_build(pebble, mode):
    """Issue 34: random local remeshes (finer and coarser), then their undo and redo steps
    (new rows anywhere), renumber one index in place (removed vertices' slots freed, removed
    faces' blanked, new ones in free slots or after the last): after each, the normals (bit for
    bit), faces drawn and picks of a new build, and after a brush move."""
    vertices, faces = pebble
    rng = np.random.default_rng(1)
    with forced(mode):
        index = SurfaceIndex(vertices, faces)
        history = []
        for step in range(5):
            center, detail = int(rng.integers(len(vertices))), [0.02, 0.08][step % 2]
            done = local_remesh(vertices, faces, center, detail, step)
            index.renumber(*done)
            assert_same_as_new_build(index, done[0], done[1], step)
            history.append((vertices, faces, done))
            vertices, faces = done[0], done[1]
        for before_vertices, before_faces, done in reversed(history[-3:]):  # undo, undo, undo
            index.renumber(before_vertices, before_faces, inverted(done[2], len(before_vertices)),
                           inverted(done[3], len(before_faces)))  # fmt: skip
            assert_same_as_new_build(index, before_vertices, before_faces)
        before_vertices, before_faces, done = history[-3]  # redo
        index.renumber(*done)
        assert_same_as_new_build(index, done[0], done[1])
        moved, changed = brush_move(done[0], 3, 0.5)
        index.update(moved, changed)
        assert_normals_of(index, moved, done[1])


def test_a_renumbering_writes_only_what_changed(pebble):
    """Issue 34: renumbering in place touches the rows of the change, not the mesh: the kept
    vertices' and faces' slots keep their rows and bits (no copy), the arrays are the same
    buffers (room to spare), the rows written are about the change's, not the mesh's."""
    vertices, faces = default_model(5)
    index = SurfaceIndex(vertices, faces)
    buffers = [index._positions, index._normals, index._faces, index._face_normals]
    done = local_remesh(vertices, faces, 7, 0.04, 0)  # ~700 of 20k faces new
    kept, kept_faces = np.flatnonzero(done[2] >= 0), np.flatnonzero(done[3] >= 0)
    slots, face_slots = index.rank[done[2][kept]], index._face_rank[done[3][kept_faces]]
    before = index._faces[face_slots].copy(), index._face_normals[face_slots].copy()
    written = index.renumber(*done)
    assert all(a is b for a, b in zip(buffers, [index._positions, index._normals, index._faces,
                                               index._face_normals], strict=True))  # fmt: skip
    assert np.array_equal(index.rank[kept], slots)  # kept rows keep their slots
    assert np.array_equal(index._face_rank[kept_faces], face_slots)
    assert np.array_equal(index._faces[face_slots], before[0])
    assert np.array_equal(index._face_normals[face_slots], before[1])
    changed = np.count_nonzero(done[3] < 0) + len(faces) - len(kept_faces)
    assert changed < len(faces) / 10 and 0 < written < 5 * changed
    assert_same_as_new_build(index, done[0], done[1])


def test_a_dynamic_topology_stroke_records_how_it_renumbered_the_mesh():
    """The mesh state's record of a dynamic-topology stroke: the faces before it and each
    row's row before (the carried faces are the old ones renumbered, the new rows after the
    others); an undo (faces from elsewhere) leaves no record."""
    from gogreen_core import Sculptor
    from gogreen_core.sculpt.brushes import Brush, BrushEvent

    vertices, faces = default_model(3)
    sculptor = Sculptor(vertices, faces, dynamic_topology=True)
    before_vertices = sculptor.vertices.copy()
    state = sculptor.remesher.mesh
    assert state.renumbering is None
    before = sculptor.faces
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    step = np.array([0.0, 0.0, 0.03 * sculptor.model_size])
    sculptor.begin_stroke(Brush("grab", radius=0.05))
    for k in range(4):
        sculptor.stroke_event(BrushEvent(center=top + k * step, delta=step))
    sculptor.end_stroke()
    assert sculptor.faces.shape != before.shape
    start, origin, face_origin = state.renumbering
    assert start is before
    n, m = np.count_nonzero(origin >= 0), np.count_nonzero(face_origin >= 0)
    assert np.all(origin[:n] >= 0) and np.all(origin[n:] < 0) and np.all(face_origin[m:] < 0)
    assert np.all(np.diff(origin[:n]) > 0) and np.all(np.diff(face_origin[:m]) > 0)
    new_row = np.full(len(before_vertices), -1)
    new_row[origin[:n]] = np.arange(n)
    assert np.array_equal(new_row[before[face_origin[:m]]], sculptor.faces[:m])
    sculptor.undo()
    assert state.renumbering is None and np.array_equal(sculptor.faces, before)
