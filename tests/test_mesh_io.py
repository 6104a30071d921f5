"""Mesh files: order-preserving round trips, clear errors, atomic saves."""

import os

import numpy as np
import pytest

from gogreen_core import mesh_io
from gogreen_core.mesh_io import MeshData, MeshFileError, load_mesh, save_mesh

SHARED = "/work/shared/meshes"


def count_obj_vertices(path: str) -> int:
    with open(path) as handle:
        return sum(1 for line in handle if line.startswith("v "))


@pytest.mark.parametrize("name", ["spot.obj", "stanford-bunny.obj", "ogre.obj"])
def test_shared_meshes_keep_vertex_order_and_round_trip(tmp_path, name):
    path = f"{SHARED}/{name}"
    mesh = load_mesh(path)
    assert len(mesh.vertices) == count_obj_vertices(path)
    with open(path) as handle:  # first vertex as written in the file
        first = next(line for line in handle if line.startswith("v ")).split()[1:4]
    assert np.array_equal(mesh.vertices[0], np.array(first, dtype=float))
    for suffix, kwargs in ((".obj", {}), (".ply", {}), (".ply", {"ascii": True}), (".off", {})):
        target = tmp_path / f"out{suffix}"
        save_mesh(mesh, target, **kwargs)
        again = load_mesh(target)
        assert np.array_equal(again.vertices, mesh.vertices), suffix
        assert np.array_equal(again.faces, mesh.faces), suffix


def test_obj_texture_coordinates_survive(tmp_path):
    mesh = load_mesh(f"{SHARED}/spot.obj")
    assert mesh.uv is not None and len(mesh.uv) > len(mesh.vertices)  # seams kept, not split
    save_mesh(mesh, tmp_path / "spot.obj")
    again = load_mesh(tmp_path / "spot.obj")
    assert np.array_equal(again.uv, mesh.uv)
    assert np.array_equal(again.uv_faces, mesh.uv_faces)


def test_stl_round_trip_keeps_triangles(tmp_path):
    mesh = load_mesh(f"{SHARED}/spot.obj")
    save_mesh(mesh, tmp_path / "spot.stl")
    again = load_mesh(tmp_path / "spot.stl")
    assert len(again.faces) == len(mesh.faces)
    corners = mesh.vertices[mesh.faces].astype(np.float32)
    assert np.array_equal(again.vertices[again.faces].astype(np.float32), corners)


def test_polygons_are_triangulated_and_negative_indices_work(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n")
    mesh = load_mesh(path)
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("empty.obj", "", "empty"),
        ("novertex.obj", "# nothing\n", "no vertices"),
        ("noface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles"),
        ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "references vertex 8"),
        ("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "vertex 0"),
        ("text.obj", "v 0 zero 0\n", "bad number"),
        ("short.obj", "v 0 0\n", "3 coordinates"),
        ("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3"),
        ("broken.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 10\n", "broken"),
        ("trunc.off", "OFF\n4 2 0\n0 0 0\n", "broken"),
        ("mesh.xyz", "1 2 3\n", "unknown format"),
    ],
)
def test_bad_files_are_rejected_with_the_file_name(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(MeshFileError) as info:
        load_mesh(path)
    assert name in str(info.value) and message in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(MeshFileError, match="no such file"):
        load_mesh(tmp_path / "absent.obj")


def test_failed_save_never_touches_the_good_file(tmp_path, monkeypatch):
    mesh = load_mesh(f"{SHARED}/spot.obj")
    target = tmp_path / "good.obj"
    save_mesh(mesh, target)
    original = target.read_bytes()
    bad = mesh.copy()
    bad.vertices[3, 1] = np.nan
    with pytest.raises(MeshFileError, match="vertex 3"):
        save_mesh(bad, target)

    def explode(*_args, **_kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(mesh_io, "_write_obj", explode)
    with pytest.raises(OSError, match="disk full"):
        save_mesh(mesh, target)
    assert target.read_bytes() == original
    assert sorted(os.listdir(tmp_path)) == ["good.obj"]  # no temporary left behind


def test_mesh_data_copy_is_deep():
    mesh = MeshData(np.zeros((3, 3)), np.array([[0, 1, 2]]))
    clone = mesh.copy()
    clone.vertices[0, 0] = 1
    assert mesh.vertices[0, 0] == 0
