"""Loop subdivision: of the whole mesh or of its unmasked part, with UVs and the mask carried,
an undo step that gives the previous mesh back exactly, a session record that replays bit for
bit, and OBJ files that keep their texture coordinates."""

import json

import numpy as np
import pytest

from app.document import Document
from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.geometry import mesh_volume
from gogreen_core.mesh.mesh_io import MeshData, load_mesh
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.mesh.subdivision import MASK_THRESHOLD, loop_subdivide, prepare_subdivision
from gogreen_core.mesh.topology import mesh_edges


def oriented_and_closed(faces):
    """Every directed edge once, and its reverse too (a closed, consistently oriented mesh)."""
    a = faces.ravel()
    b = np.roll(faces, -1, axis=1).ravel()
    directed = set(zip(a.tolist(), b.tolist(), strict=True))
    return len(directed) == len(a) and all((y, x) in directed for x, y in directed)


def test_loop_rules_on_an_icosphere():
    vertices, faces = icosphere(2)
    edges = mesh_edges(faces, len(vertices))
    result = loop_subdivide(vertices, faces)
    assert len(result.vertices) == len(vertices) + len(edges)  # 162 + 480 = 642: ≈ 4×
    assert len(result.faces) == 4 * len(faces)
    assert oriented_and_closed(result.faces)
    # the rules by hand for one edge and one old vertex (valence 6 on an icosphere's face)
    (a, b), k = edges.ends[0], 0
    sides = np.flatnonzero(np.any(edges.face_edges == k, axis=1))
    opposite = [int(np.setdiff1d(faces[f], [a, b])[0]) for f in sides]
    expected = 0.375 * (vertices[a] + vertices[b]) + 0.125 * vertices[opposite].sum(axis=0)
    np.testing.assert_allclose(result.vertices[len(vertices) + k], expected, rtol=0, atol=1e-15)
    v = int(np.flatnonzero(np.bincount(edges.ends.ravel()) == 6)[0])
    ring = np.unique(edges.ends[np.any(edges.ends == v, axis=1)])
    ring = ring[ring != v]
    beta = (0.625 - (0.375 + 0.25 * np.cos(2 * np.pi / 6)) ** 2) / 6
    expected = (1 - 6 * beta) * vertices[v] + beta * vertices[ring].sum(axis=0)
    np.testing.assert_allclose(result.vertices[v], expected, rtol=0, atol=1e-15)
    # smoothing, not blowing up: within 2 % of the sphere's volume
    assert 0.97 < mesh_volume(result.vertices, result.faces) / mesh_volume(vertices, faces) < 1.0


def test_open_meshes_use_the_boundary_rules():
    vertices, faces = icosphere(2)
    keep = vertices[faces].mean(axis=1)[:, 2] > -0.3
    faces = faces[keep]
    result = loop_subdivide(vertices, faces)
    edges = mesh_edges(result.faces, len(result.vertices))
    assert set(np.unique(edges.face_count)) == {1, 2}
    rim = mesh_edges(faces, len(vertices))
    k = int(np.flatnonzero(rim.face_count == 1)[0])
    a, b = rim.ends[k]
    np.testing.assert_array_equal(
        result.vertices[len(vertices) + k], 0.5 * (vertices[a] + vertices[b])
    )


def test_the_unmasked_part_alone_stays_watertight_and_the_masked_part_still():
    vertices, faces = icosphere(3)
    mask = (vertices[:, 0] > 0.1).astype(float)
    refine = np.all(mask[faces] < MASK_THRESHOLD, axis=1)
    result = loop_subdivide(vertices, faces, refine=refine, mask=mask)
    assert oriented_and_closed(result.faces)
    held = mask == 1.0
    assert np.array_equal(result.vertices[: len(vertices)][held], vertices[held])
    assert len(result.faces) < 4 * len(faces) and len(result.faces) > 2 * len(faces)
    assert result.mask is not None and np.array_equal(result.mask[: len(vertices)], mask)
    # the masked side keeps its triangles: each of its faces (all corners held) is whole
    whole = {tuple(f) for f in result.faces.tolist()}
    untouched = [f for f in faces.tolist() if all(mask[f] == 1.0)]
    assert untouched and sum(tuple(f) in whole for f in untouched) > 0.8 * len(untouched)


def test_uv_corners_are_subdivided_with_their_seams(made_textured):
    mesh = load_mesh(made_textured.path)
    result = loop_subdivide(mesh.vertices, mesh.faces, uv=mesh.uv, uv_faces=mesh.uv_faces)
    assert result.uv_faces.shape == result.faces.shape
    assert len(result.uv) > len(mesh.uv)
    # each child corner's UV is its parent's corner or the midpoint of a parent side's UVs
    parent_uv = mesh.uv[mesh.uv_faces[0]]
    child = result.uv[result.uv_faces[0]]
    assert np.array_equal(child[0], parent_uv[0])
    np.testing.assert_array_equal(child[1], 0.5 * (parent_uv[0] + parent_uv[1]))
    # a seam stays a seam: more UV rows than vertices, as before
    assert len(result.uv) - len(result.vertices) >= len(mesh.uv) - len(mesh.vertices)


def test_a_per_vertex_uv_layout_stays_per_vertex():
    vertices, faces = icosphere(2)
    result = loop_subdivide(vertices, faces, uv=vertices[:, :2], uv_faces=faces)
    assert np.array_equal(result.uv_faces, result.faces)
    edges = mesh_edges(faces, len(vertices))
    np.testing.assert_array_equal(
        result.uv[len(vertices) :],
        0.5 * (vertices[edges.ends[:, 0], :2] + vertices[edges.ends[:, 1], :2]),
    )


def test_subdivide_is_an_undo_step_that_gives_the_mesh_back_exactly():
    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.0, 0.05, 0.1])])
    sculpted = sculptor.vertices.copy()
    model_size, origin = sculptor.model_size, sculptor.origin.copy()
    sculptor.subdivide()
    assert len(sculptor.vertices) == 4 * len(vertices) - 6  # V + E, E = 3V − 6 (closed)
    assert len(sculptor.faces) == 4 * len(faces) and sculptor.faces.dtype == np.int64
    assert sculptor.model_size == model_size and np.array_equal(sculptor.origin, origin)
    subdivided = sculptor.mesh
    assert sculptor.undo() == "subdivide"
    assert np.array_equal(sculptor.vertices, sculpted) and np.array_equal(sculptor.faces, faces)
    assert sculptor.undo() == "Wide grab stroke"
    assert np.array_equal(sculptor.vertices, vertices)
    assert sculptor.redo() == "Wide grab stroke" and sculptor.redo() == "subdivide"
    assert np.array_equal(sculptor.vertices, subdivided.vertices)
    assert np.array_equal(sculptor.faces, subdivided.faces)
    # sculpting goes on on the finer mesh; the mask carries over
    sculptor.apply_brush(Brush("smooth", radius=0.2), [BrushEvent(top, amount=1.0)])
    sculptor.apply_brush(Brush("mask", radius=0.1), [BrushEvent(top, amount=1.0)])
    assert sculptor.history.memory_bytes > subdivided.nbytes


def test_subdivisions_replay_bit_for_bit(made_textured):
    mesh = load_mesh(made_textured.path)
    sculptor = Sculptor(mesh.vertices, mesh.faces, uv=mesh.uv, uv_faces=mesh.uv_faces)
    top = mesh.vertices[int(np.argmax(mesh.vertices[:, 2]))]
    sculptor.apply_brush(Brush("mask", radius=0.1), [BrushEvent(top, amount=1.0)])
    sculptor.subdivide(unmasked_only=True)
    sculptor.apply_brush(Brush("grab", radius=0.1), [BrushEvent(-top, [0.0, 0.05, 0.0])])
    sculptor.mask.clear()
    sculptor.subdivide()
    sculptor.undo()
    sculptor.redo()
    session = json.loads(json.dumps(sculptor.session()))
    assert session["mesh"]["vertices"] == len(mesh.vertices)  # the mesh it started from
    assert [op["op"] for op in session["operations"]].count("subdivide") == 2
    again = Sculptor.from_session(session, mesh.vertices, mesh.faces, mesh.uv, mesh.uv_faces)
    again.replay(session["operations"])
    for name in ("vertices", "faces", "mask", "uv", "uv_faces"):
        assert np.array_equal(getattr(again.mesh, name), getattr(sculptor.mesh, name)), name
    # a replay that fails after a subdivision puts the first mesh back
    before = again.mesh
    with pytest.raises(ValueError, match="operations\\[1\\]"):
        again.replay([{"op": "subdivide"}, {"op": "constraint_remove", "index": 0}])
    assert np.array_equal(again.faces, before.faces) and len(again.vertices) == len(before.vertices)


def test_a_prepared_subdivision_is_adopted_only_for_its_own_mesh():
    vertices, faces = icosphere(2)
    sculptor = Sculptor(vertices, faces)
    prepared = prepare_subdivision(sculptor.mesh)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.0, 0.05, 0.1])])
    with pytest.raises(ValueError, match="another mesh"):
        sculptor.subdivide(prepared=prepared)
    assert len(sculptor.vertices) == len(vertices)
    with pytest.raises(ValueError, match="another mesh"):
        sculptor.subdivide(unmasked_only=True, prepared=prepare_subdivision(sculptor.mesh))
    sculptor.subdivide(prepared=prepare_subdivision(sculptor.mesh))
    direct = Sculptor(vertices, faces)
    direct.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.0, 0.05, 0.1])])
    direct.subdivide()
    assert np.array_equal(direct.vertices, sculptor.vertices)


def test_obj_output_keeps_the_subdivided_uvs(made_textured, tmp_path):
    document = Document.open(str(made_textured.path))
    document.sculptor.subdivide()
    assert document.dirty
    saved = load_mesh(document.save(str(tmp_path / "finer.obj")))
    now = document.sculptor.mesh
    assert not document.dirty
    assert len(saved.faces) == 4 * len(made_textured.faces)
    assert saved.uv is not None and saved.uv_faces is not None
    np.testing.assert_allclose(saved.uv[saved.uv_faces], now.uv[now.uv_faces], atol=1e-6)
    np.testing.assert_allclose(saved.vertices[saved.faces], now.vertices[now.faces], atol=1e-6)
    document.sculptor.undo()
    assert document.dirty  # the file now has the finer mesh


def test_the_mesh_property_is_a_copy():
    vertices, faces = icosphere(1)
    sculptor = Sculptor(vertices, faces, uv=vertices[:, :2], uv_faces=faces)
    snapshot = sculptor.mesh
    snapshot.vertices[0] = 9.0
    assert not np.array_equal(sculptor.vertices[0], snapshot.vertices[0])
    assert isinstance(MeshData(snapshot.vertices, snapshot.faces).faces, np.ndarray)
    with pytest.raises(ValueError, match="uv_faces"):
        Sculptor(vertices, faces, uv=vertices[:, :2], uv_faces=faces[:3])


def test_gogreen_replay_writes_the_subdivided_mesh_with_its_uvs(made_textured, tmp_path):
    from gogreen_core.interaction.batch import main

    mesh = load_mesh(made_textured.path)
    sculptor = Sculptor(mesh.vertices, mesh.faces, uv=mesh.uv, uv_faces=mesh.uv_faces)
    sculptor.subdivide()
    top = mesh.vertices[int(np.argmax(mesh.vertices[:, 2]))]
    sculptor.apply_brush(Brush("smooth", radius=0.1), [BrushEvent(top, amount=1.0)])
    session = tmp_path / "session.json"
    session.write_text(json.dumps(sculptor.session()))
    out = tmp_path / "out.obj"
    assert main(["replay", str(session), str(made_textured.path), "-o", str(out), "-q"]) == 0
    written = load_mesh(out)
    assert len(written.faces) == len(sculptor.faces) and written.uv is not None
    np.testing.assert_allclose(written.vertices, sculptor.vertices, atol=1e-6)
    # a smooth stroke from the command line takes the pressure per event
    smoothed = tmp_path / "smoothed.obj"
    args = ["deform", str(made_textured.path), "-o", str(smoothed), "--brush", "smooth"]
    args += ["--center", *map(str, top), "--amount", "1", "--events", "3", "-q"]
    assert main(args) == 0
    assert not np.array_equal(load_mesh(smoothed).vertices, mesh.vertices)


def test_pins_hold_across_a_subdivision_and_its_undo():
    """Pins are points in space, not vertex numbers: they drag the finer mesh, and undo of
    the subdivision gives back the mesh they dragged before."""
    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    pin = sculptor.add_constraint(top)
    sculptor.add_constraint(-top)
    sculptor.drag_constraint(pin, np.array([0.0, 0.0, 0.05]))
    dragged = sculptor.vertices.copy()
    sculptor.subdivide()
    u = sculptor.drag_constraint(pin, np.array([0.0, 0.05, 0.0]))
    assert u.shape == (len(sculptor.vertices), 3) and np.any(u)
    np.testing.assert_allclose(sculptor.constraint_points[pin], top + np.array([0.0, 0.05, 0.05]))
    assert sculptor.undo() == "constraint drag" and sculptor.undo() == "subdivide"
    assert np.array_equal(sculptor.vertices, dragged)
    np.testing.assert_allclose(sculptor.constraint_points[pin], top + np.array([0.0, 0.0, 0.05]))
