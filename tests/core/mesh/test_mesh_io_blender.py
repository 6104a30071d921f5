"""Files in the layouts Blender writes by default load as the surface Blender had: same area,
closed where it is closed, texture coordinates kept; saved PLY keeps them too."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from mesh_io_models import (
    U_PRISM_AREA,
    Model,
    binary_stl,
    blender_obj,
    blender_ply,
    blender_ply_split,
    edges_used_once,
    triangle_area,
    u_prism,
    uv_sphere,
)

from gogreen_core.mesh.mesh_io import MeshData, load_mesh, save_mesh


def corner_uv_of_triangles(model: Model) -> np.ndarray:
    """Per corner of each fan triangle (T, 3, 2): the texture coordinate the file gives it."""
    rows = []
    for uvs in model.corner_uv:
        rows += [[uvs[0], uvs[j], uvs[j + 1]] for j in range(1, len(uvs) - 1)]
    return np.array(rows)


def test_the_models_are_what_they_claim():
    prism, sphere = u_prism(), uv_sphere()
    assert prism.area() == U_PRISM_AREA
    assert edges_used_once(prism.triangles) == edges_used_once(sphere.triangles) == 0
    assert len(blender_ply_split(sphere)[0]) > len(
        sphere.vertices
    )  # split at the seam and the poles
    assert len(blender_ply_split(prism)[0]) > len(prism.vertices)


@pytest.mark.parametrize("smooth", ["s 0", "s off", "s 1"])
def test_blender_obj_with_n_gons_loads_the_same_surface(tmp_path: Path, smooth):
    prism, sphere = u_prism(), uv_sphere()
    path = tmp_path / "scene.obj"
    path.write_text(blender_obj({"Prism": prism, "Sphere": sphere}, smooth))
    mesh = load_mesh(path)
    assert len(mesh.vertices) == len(prism.vertices) + len(sphere.vertices)  # OBJ shares them
    shift = len(prism.vertices)
    sphere_faces = mesh.faces[len(prism.triangles) :] - shift
    assert triangle_area(mesh.vertices, mesh.faces[: len(prism.triangles)]) == U_PRISM_AREA
    assert triangle_area(mesh.vertices[shift:], sphere_faces) == pytest.approx(sphere.area())
    assert edges_used_once(mesh.faces) == 0
    assert np.array_equal(sphere_faces, sphere.triangles)  # convex faces: the fans, in order
    corner_uv = mesh.uv[mesh.uv_faces[len(prism.triangles) :]]
    assert np.allclose(corner_uv, corner_uv_of_triangles(sphere), atol=5e-7)  # six decimals


@pytest.mark.parametrize("ascii", [False, True])
def test_blender_ply_with_uv_seams_loads_closed_with_its_uvs(tmp_path: Path, ascii):
    sphere = uv_sphere()
    path = tmp_path / "sphere.ply"
    path.write_bytes(blender_ply(sphere, ascii=ascii))
    mesh = load_mesh(path)
    assert len(mesh.vertices) == len(sphere.vertices)  # the seam copies are one vertex again
    assert edges_used_once(mesh.faces) == 0
    assert triangle_area(mesh.vertices, mesh.faces) == pytest.approx(sphere.area(), rel=1e-6)
    expected = corner_uv_of_triangles(sphere).astype(np.float32).astype(np.float64)
    assert np.array_equal(mesh.uv[mesh.uv_faces], expected)
    # Same triangles as Blender's vertex numbers, renumbered by first appearance.
    positions = blender_ply_split(sphere)[0].astype(np.float32)
    assert np.array_equal(mesh.vertices[mesh.faces], positions[mesh.uv_faces].astype(np.float64))


def test_a_seamed_ply_saves_back_with_its_uvs(tmp_path: Path):
    sphere = uv_sphere()
    source = tmp_path / "sphere.ply"
    source.write_bytes(blender_ply(sphere))
    mesh = load_mesh(source)
    for name, options in [("binary.ply", {}), ("ascii.ply", {"ascii": True})]:
        save_mesh(mesh, tmp_path / name, **options)
        header = (tmp_path / name).read_bytes().split(b"end_header")[0]
        assert b"property double s\nproperty double t\n" in header
        again = load_mesh(tmp_path / name)
        assert np.array_equal(again.vertices, mesh.vertices)  # same vertices, same order
        assert np.array_equal(again.faces, mesh.faces)
        assert np.array_equal(again.uv[again.uv_faces], mesh.uv[mesh.uv_faces])
        assert edges_used_once(again.faces) == 0
    save_mesh(mesh, tmp_path / "copy.obj")  # and as OBJ: texture coordinates per corner
    again = load_mesh(tmp_path / "copy.obj")
    assert np.array_equal(again.uv[again.uv_faces], mesh.uv[mesh.uv_faces])


def test_a_seamed_prism_with_concave_caps_keeps_its_area_and_uvs(tmp_path: Path):
    prism = u_prism()
    path = tmp_path / "prism.ply"
    path.write_bytes(blender_ply(prism))
    mesh = load_mesh(path)
    assert len(mesh.vertices) == 16 and edges_used_once(mesh.faces) == 0
    assert triangle_area(mesh.vertices, mesh.faces) == U_PRISM_AREA
    # Each corner's texture coordinate is the one of that corner of its polygon.
    polygon_uv = {
        (p, v): uv
        for p, (poly, uvs) in enumerate(zip(prism.polygons, prism.corner_uv, strict=True))
        for v, uv in zip(poly, uvs, strict=True)
    }
    owner = np.repeat(np.arange(len(prism.polygons)), [len(p) - 2 for p in prism.polygons])
    file_vertex_to_model = {tuple(x): i for i, x in enumerate(prism.vertices.tolist())}
    for t, (face, uv_face) in enumerate(zip(mesh.faces, mesh.uv_faces, strict=True)):
        for v, u in zip(face, uv_face, strict=True):
            model_vertex = file_vertex_to_model[tuple(mesh.vertices[v].tolist())]
            expected = np.float32(polygon_uv[(int(owner[t]), model_vertex)])
            assert np.array_equal(mesh.uv[u], expected.astype(np.float64))


def test_a_blender_ply_without_uvs_keeps_its_vertices_as_listed(tmp_path: Path):
    """export_uv off: no splits, no attributes, nothing is welded."""
    prism = u_prism()
    path = tmp_path / "plain.ply"
    path.write_bytes(blender_ply(prism, export_uv=False))
    mesh = load_mesh(path)
    assert np.array_equal(mesh.vertices, prism.vertices) and mesh.uv is None
    assert triangle_area(mesh.vertices, mesh.faces) == U_PRISM_AREA
    assert edges_used_once(mesh.faces) == 0


def test_ply_vertices_at_one_position_are_joined_when_the_file_has_attributes(tmp_path: Path):
    """Two triangles meeting at one point: with UVs in the file they are welded there, equal
    UVs (an exporter that writes a vertex per corner, or UVs equal after rounding to float32)
    or not; a file of positions only keeps its vertices as listed."""
    header = (
        "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
        "property float z\nproperty float s\nproperty float t\nelement face 2\n"
        "property list uchar uint vertex_indices\nend_header\n"
    )
    rows = "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n1 1 0 1 1\n2 1 0 0 1\n2 2 0 0 0\n3 0 1 2\n3 3 4 5\n"
    path = tmp_path / "touch.ply"
    path.write_text(header + rows)
    mesh = load_mesh(path)
    assert len(mesh.vertices) == 5 and mesh.faces.tolist() == [[0, 1, 2], [2, 3, 4]]
    assert mesh.uv_faces.tolist() == [[0, 1, 2], [3, 4, 5]]  # the file's corners
    path.write_text(header + rows.replace("1 1 0 1 1\n2 1", "1 1 0 0.5 1\n2 1"))  # a seam
    assert len(load_mesh(path).vertices) == 5
    plain = header.replace("property float s\nproperty float t\n", "")
    positions = "0 0 0\n1 0 0\n1 1 0\n1 1 0\n2 1 0\n2 2 0\n3 0 1 2\n3 3 4 5\n"
    path.write_text(plain + positions)
    assert len(load_mesh(path).vertices) == 6


@pytest.mark.parametrize("model", [u_prism, uv_sphere])
def test_blender_binary_stl_loads_closed_with_its_area(tmp_path: Path, model):
    shape = model()
    path = tmp_path / "model.stl"
    path.write_bytes(binary_stl(shape.vertices, shape.triangles))
    mesh = load_mesh(path)
    assert len(mesh.vertices) == len(shape.vertices)
    assert edges_used_once(mesh.faces) == 0
    rounded = shape.vertices.astype(np.float32).astype(np.float64)
    assert triangle_area(mesh.vertices, mesh.faces) == pytest.approx(
        triangle_area(rounded, shape.triangles), rel=1e-12
    )
    save_mesh(mesh, tmp_path / "again.stl")
    again = load_mesh(tmp_path / "again.stl")
    assert np.array_equal(again.vertices, mesh.vertices) and np.array_equal(again.faces, mesh.faces)


def test_saved_stl_is_a_valid_binary_stl(tmp_path: Path):
    mesh = MeshData(np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]]), np.array([[0, 1, 2]]))
    save_mesh(mesh, tmp_path / "t.stl")
    data = (tmp_path / "t.stl").read_bytes()
    assert len(data) == 84 + 50 and not data.startswith(b"solid")
    assert np.frombuffer(data, "<u4", 1, 80)[0] == 1
    assert np.frombuffer(data, "<f4", 12, 84).tolist() == [0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0]
