"""Mesh files: order-preserving loads, exact round trips, clear errors, atomic saves."""

from __future__ import annotations

import json
import os
import struct
from pathlib import Path

import numpy as np
import pytest

from gogreen_core.mesh.mesh_io import (
    MeshData,
    MeshFileError,
    atomic,
    load_mesh,
    obj,
    ply,
    save_mesh,
    text,
)

SHARED_MESHES = ["spot.obj", "stanford-bunny.obj", "ogre.obj"]
MADE_MESHES = ["made_textured", "made_open_tiny", "made_huge"]  # their stand-ins (conftest.py)
TEXT_FORMATS = [(".obj", {}), (".ply", {}), (".ply", {"ascii": True}), (".off", {})]


def obj_records(path: Path, tag: str) -> list[list[str]]:
    """The fields of every ``tag`` line of an OBJ file, read independently of mesh_io."""
    with open(path) as handle:
        return [line.split()[1:] for line in handle if line.split()[:1] == [tag]]


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.ascontiguousarray(a, dtype=np.float64), np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def write(path: Path, content: str | bytes) -> Path:
    if isinstance(content, str):
        path.write_text(content)
    else:
        path.write_bytes(content)
    return path


TRIANGLE = MeshData(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))


# -- the shared meshes and the project-made ones ----------------------------------------------
@pytest.fixture(scope="module", params=SHARED_MESHES + MADE_MESHES)
def listed(request):
    """An OBJ file (a shared mesh, skipped when absent, or a made one) and its loaded mesh."""
    if request.param in MADE_MESHES:
        path = request.getfixturevalue(request.param).path
    else:
        path = request.getfixturevalue("shared_mesh")(request.param)
    return path, load_mesh(path)


def test_obj_meshes_keep_every_vertex_in_file_order(listed):
    path, mesh = listed
    listed_vertices = np.array([fields[:3] for fields in obj_records(path, "v")], dtype=np.float64)
    assert mesh.vertices.dtype == np.float64 and mesh.faces.dtype == np.int64
    assert len(mesh.vertices) == len(listed_vertices)  # no seam splitting, no merging
    assert same_bits(mesh.vertices, listed_vertices)
    sides = [len(fields) - 2 for fields in obj_records(path, "f")]  # triangles per polygon
    assert len(mesh.faces) == sum(sides)
    assert mesh.source == str(path)


@pytest.mark.parametrize(("suffix", "options"), TEXT_FORMATS)
def test_obj_meshes_round_trip_bit_for_bit(listed, tmp_path, suffix, options):
    _, mesh = listed
    target = tmp_path / f"out{suffix}"
    save_mesh(mesh, target, **options)
    again = load_mesh(target)
    assert same_bits(again.vertices, mesh.vertices)
    assert np.array_equal(again.faces, mesh.faces)


def edges_used_once(faces: np.ndarray) -> int:
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


def test_made_meshes_stand_for_the_shared_ones(made_textured, made_open_tiny, made_huge):
    """The properties each shared mesh brings are present in its project-made stand-in."""
    textured = load_mesh(made_textured.path)
    assert len(textured.uv) > len(textured.vertices)  # UV seams, like Spot
    assert any(len(fields) > 3 for fields in obj_records(made_textured.path, "f"))  # quads
    assert obj_records(made_textured.path, "vn")
    assert same_bits(textured.vertices, made_textured.vertices)
    assert np.array_equal(textured.faces, made_textured.faces)
    open_tiny = load_mesh(made_open_tiny.path)
    assert edges_used_once(open_tiny.faces) > 0  # holes, like the bunny
    assert 0.1 < np.ptp(open_tiny.vertices, axis=0).max() < 0.2 and len(open_tiny.vertices) > 3000
    assert edges_used_once(made_textured.faces) == edges_used_once(made_huge.faces) == 0
    assert 25 < np.ptp(load_mesh(made_huge.path).vertices, axis=0).max() < 35  # like the Ogre


@pytest.fixture(params=["made", "spot.obj"])
def textured_obj(request, made_textured, shared_mesh) -> Path:
    return made_textured.path if request.param == "made" else shared_mesh(request.param)


def test_texture_coordinates_load_and_survive_a_round_trip(textured_obj, tmp_path):
    path = textured_obj
    mesh = load_mesh(path)
    uv = np.array([fields[:2] for fields in obj_records(path, "vt")], dtype=np.float64)
    corners = [[int(c.split("/")[1]) - 1 for c in fields] for fields in obj_records(path, "f")]
    fanned = [[c[0], c[k], c[k + 1]] for c in corners for k in range(1, len(c) - 1)]
    assert same_bits(mesh.uv, uv)  # Spot: 3225 texture coordinates for 2930 vertices: seams kept
    assert len(mesh.uv) > len(mesh.vertices)
    assert np.array_equal(mesh.uv_faces, fanned)
    save_mesh(mesh, tmp_path / "copy.obj")
    again = load_mesh(tmp_path / "copy.obj")
    assert same_bits(again.vertices, mesh.vertices)
    assert same_bits(again.uv, mesh.uv)
    assert np.array_equal(again.uv_faces, mesh.uv_faces)


def test_stl_corners_are_welded_into_the_same_closed_surface(made_textured, tmp_path):
    mesh = load_mesh(made_textured.path)
    save_mesh(mesh, tmp_path / "m.stl")
    again = load_mesh(tmp_path / "m.stl")
    corners = mesh.vertices[mesh.faces].astype(np.float32)  # STL is float32
    assert np.array_equal(again.vertices[again.faces], corners.astype(np.float64))
    assert len(again.vertices) == len(np.unique(mesh.faces))  # one vertex per position
    first_use = np.unique(again.faces.ravel(), return_index=True)[1]
    assert np.all(np.diff(first_use) > 0)  # numbered in order of first appearance
    assert edges_used_once(again.faces) == edges_used_once(mesh.faces) == 0  # closed


# -- exact floats ------------------------------------------------------------------------------
@pytest.mark.parametrize(("suffix", "options"), TEXT_FORMATS)
def test_awkward_floats_reload_bit_for_bit(tmp_path, suffix, options):
    rng = np.random.default_rng(1)
    vertices = rng.normal(size=(200, 3)) * 10.0 ** rng.integers(-300, 300, size=(200, 3))
    vertices[0] = [-0.0, 5e-324, 1e308]  # negative zero, smallest subnormal, huge
    vertices[1] = [0.1, 1 / 3, -2.2250738585072014e-308]  # smallest normal
    vertices[2] = [np.pi, np.e, np.nextafter(1.0, 2.0)]
    faces = rng.integers(0, 200, size=(100, 3))
    save_mesh(MeshData(vertices, faces), tmp_path / f"a{suffix}", **options)
    again = load_mesh(tmp_path / f"a{suffix}")
    assert same_bits(again.vertices, vertices)
    assert np.array_equal(again.faces, faces)


# -- OBJ details -------------------------------------------------------------------------------
def test_obj_polygons_corner_forms_negative_indices_and_comments(tmp_path):
    path = write(
        tmp_path / "forms.obj",
        "# a comment\n"
        "v 0 0 0\nv 1 0 0  # trailing comment\nv 1 1 0\nv 0 1 0\nv -0.5 0.5 0 1.0\n"
        "vn 0 0 1\n"
        "g group\nusemtl m\ns off\n\n"
        "f 1//1 2//1 3//1 4//1\n"  # quad with normals only
        "f -2 -3 -1\n"  # relative indices
        "f 1 2 3 4 5\n",  # convex pentagon: fanned from its first corner
    )
    mesh = load_mesh(path)
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [3, 2, 4], [0, 1, 2], [0, 2, 3], [0, 3, 4]]
    assert mesh.uv is None and len(mesh.vertices) == 5


def test_obj_with_texture_coordinates_on_some_faces_round_trips(tmp_path):
    path = write(
        tmp_path / "mixed.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
        "f 1/1/1 2/2/1 3/3/1\nf 2 4 3\nf -3/-1 -2/-2 -1/-3\n",
    )
    mesh = load_mesh(path)
    assert mesh.uv_faces.tolist() == [[0, 1, 2], [-1, -1, -1], [2, 1, 0]]
    save_mesh(mesh, tmp_path / "again.obj")
    again = load_mesh(tmp_path / "again.obj")
    assert np.array_equal(again.faces, mesh.faces)
    assert np.array_equal(again.uv_faces, mesh.uv_faces) and same_bits(again.uv, mesh.uv)


def test_obj_faces_may_come_before_their_vertices(tmp_path):
    mesh = load_mesh(write(tmp_path / "fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"))
    assert mesh.faces.tolist() == [[0, 1, 2]]


# -- PLY, OFF and STL details ------------------------------------------------------------------
PLY_ASCII = (
    "ply\nformat ascii 1.0\ncomment c\nelement vertex {}\nproperty float x\nproperty float y\n"
    "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n"
)
SQUARE = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"


def test_ascii_ply_with_unusual_but_valid_numbers(tmp_path):
    # read whole-array; the last two lines only by the token-by-token fallback
    content = PLY_ASCII.format(3, 1) + "+1 2.5E3\t-.5\n1_0.0\x1c0 0\n0 1 0\n3 0 1 2\n"
    path = tmp_path / "u.ply"
    path.write_bytes(content.encode("utf-8"))
    mesh = load_mesh(path)
    assert mesh.vertices.tolist() == [[1, 2500, -0.5], [10, 0, 0], [0, 1, 0]]


def test_ascii_ply_polygons_are_fan_triangulated(tmp_path):
    content = PLY_ASCII.format(5, 2) + SQUARE + "0 0 1\n4 0 1 2 3\n5 0 1 2 3 4\n"
    mesh = load_mesh(write(tmp_path / "p.ply", content))
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3], [0, 3, 4]]


def big_endian_ply(cut: int = 0) -> bytes:
    """Binary big-endian PLY with float32 positions, an extra vertex property, an extra face
    property and faces of two sizes, as other tools write them."""
    header = (
        b"ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\n"
        b"property float y\nproperty float z\nproperty uchar red\nelement face 2\n"
        b"property list uchar int vertex_indices\nproperty int flags\nend_header\n"
    )
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0.1, 1, 0)]
    body = b"".join(struct.pack(">fffB", *p, 200) for p in corners)
    body += struct.pack(">B3ii", 3, 0, 1, 2, 7) + struct.pack(">B4ii", 4, 0, 1, 2, 3, 7)
    return header + body[: len(body) - cut]


def test_binary_big_endian_ply_with_extra_properties(tmp_path):
    mesh = load_mesh(write(tmp_path / "be.ply", big_endian_ply()))
    assert mesh.vertices[3].tolist() == [np.float32(0.1), 1.0, 0.0]
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 1, 2], [0, 2, 3]]


def test_off_variants(tmp_path):
    quad = load_mesh(write(tmp_path / "q.off", "OFF\n# comment\n4 1 0\n" + SQUARE + "4 0 1 2 3\n"))
    assert quad.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    coloured = load_mesh(
        write(
            tmp_path / "c.off",
            "COFF 3 1 0\n0 0 0 9 9 9 1\n1 0 0 9 9 9 1\n0 1 0 9 9 9 1\n3 0 1 2 0.5 0.5 0.5\n",
        )
    )
    assert coloured.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    assert coloured.faces.tolist() == [[0, 1, 2]]


def test_ascii_stl(tmp_path):
    facet = "facet normal 0 0 1\nouter loop\n{}endloop\nendfacet\n"
    corners = [
        "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n",
        "vertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n",
    ]
    text = "solid t\n" + "".join(facet.format(c) for c in corners) + "endsolid t\n"
    mesh = load_mesh(write(tmp_path / "t.stl", text))
    assert len(mesh.vertices) == 4 and mesh.faces.tolist() == [[0, 1, 2], [1, 3, 2]]
    assert mesh.vertices[3].tolist() == [1, 1, 0]


# -- errors ------------------------------------------------------------------------------------
def cut_binary_ply(tmp_path: Path, cut: int) -> bytes:
    save_mesh(MeshData(np.zeros((4, 3)), [[0, 1, 2], [0, 2, 3]]), tmp_path / "src.ply")
    data = (tmp_path / "src.ply").read_bytes()
    return data[:-cut] if cut > 0 else data + b"\x01\x02"


def binary_ply_with(face: bytes, index_type: str = "int") -> bytes:
    """Little-endian PLY of 3 vertices and one face whose record (after its list length, an
    int) is ``face``: a hostile length or index."""
    header = (
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
        "property double y\nproperty double z\nelement face 1\n"
        f"property list int {index_type} vertex_indices\nend_header\n"
    )
    body = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype="<f8").tobytes()
    return header.encode() + body + face


BAD_FILES = [
    # OBJ
    ("blank.obj", " \n\n", "the file is empty"),
    ("novertex.obj", "# nothing\nvt 0 0\n", "no vertices"),
    ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
    ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\nf 1 2 9\n",
     "range.obj, line 6: face 2 references vertex 9 but the file has 3 vertices"),
    ("before.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -5\n", "line 3: relative vertex index -5"),
    ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "start at 1"),
    ("nan.obj", "v 0 0 0\n# c\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "line 3: vertex 2 has a non-finite"),
    ("inf.obj", "v 0 0 0\nv 1 0 -inf\nv 0 1 0\nf 1 2 3\n", "vertex 2 has a non-finite"),
    ("text.obj", "v 0 zero 0\n", "line 1: bad number"),
    ("short.obj", "v 0 0\n", "3 coordinates"),
    ("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3 corners"),
    ("badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "bad vertex index 'x'"),
    ("vtrange.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n",
     "line 5: face references texture coordinate 2 but the file has 1"),
    ("vtpartial.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n", "lack a texture"),
    ("binary.obj", b"\x00\xff\x13" * 50, "line 1: unknown statement"),
    ("unknown.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvv 1 1 1\nf 1 2 3\n",
     "line 4: unknown statement 'vv'"),
    ("hugeindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n",
     "line 4: vertex index 99999999999999999999 is out of range"),
    ("hugeuv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/99999999999999999999\n",
     "line 5: texture coordinate index 99999999999999999999 is out of range"),
    ("hugerelative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999999999999999999\n",
     "line 4: relative vertex index -99999999999999999999 points before the first"),
    ("hugecoordinate.obj", "v 0 0 0\nv 1 0 1e400\nv 0 1 0\nf 1 2 3\n",
     "line 2: vertex 2 has a non-finite coordinate [1.0, 0.0, inf]"),
    ("nanuv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt nan 1\nf 1/1 2/1 3/2\n",
     "line 5: texture coordinate 2 has a non-finite value"),
    # PLY
    ("empty.ply", "", "the file is empty"),
    ("notply.ply", "hello\n", "not a PLY file"),
    ("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header'"),
    ("badheader.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty quux x\nend_header\n",
     "header line 4"),
    ("noformat.ply", "ply\nelement vertex 0\nend_header\n", "no 'format'"),
    ("truncated.ply", PLY_ASCII.format(4, 2) + SQUARE + "3 0 1 2\n", "truncated"),
    ("extra.ply", PLY_ASCII.format(4, 1) + SQUARE + "3 0 1 2\n3 0 2 3\n", "do not match"),
    ("badnumber.ply", PLY_ASCII.format(4, 1) + "0 0 0\n1 0 0\n1 x 0\n0 1 0\n3 0 1 2\n",
     "bad number 'x'"),
    ("nan.ply", PLY_ASCII.format(4, 1) + "0 0 0\n1 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n",
     "vertex 2 has a non-finite"),
    ("range.ply", PLY_ASCII.format(4, 2) + SQUARE + "3 0 1 2\n3 0 2 4\n",
     "range.ply: face 1 references vertex 4 but the file has 4 vertices"),
    ("negative.ply", PLY_ASCII.format(4, 1) + SQUARE + "3 0 -1 2\n", "references vertex -1"),
    ("fraction.ply", PLY_ASCII.format(4, 1) + SQUARE + "3 0 1.5 2\n", "not a whole number"),
    ("noface.ply", PLY_ASCII.format(4, 0) + SQUARE, "no faces"),
    ("nopositions.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float q\n"
     "end_header\n1\n", "no vertex positions"),
    ("bigendian.ply", big_endian_ply(cut=3), "truncated"),
    ("hugeindex.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 1e30\n",
     "hugeindex.ply: face 0 references vertex 1e+30 but the file has 3 vertices"),
    ("longindex.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n",
     "face 0 references vertex 1e+20 but the file has 3 vertices"),
    ("nanindex.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 nan 2\n",
     "face 0 has vertex index nan, which is not a whole number"),
    ("infindex.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -inf\n",
     "face 0 has vertex index -inf, which is not a whole number"),
    ("nanlength.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\nnan 0 1 2\n",
     "bad list length nan in element 'face'"),
    ("negativelength.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n-1 0 1 2\n",
     "bad list length -1.0 in element 'face'"),
    ("hugelength.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n1e30 0 1 2\n",
     "truncated"),
    ("hugecoordinate.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1e400 0\n3 0 1 2\n",
     "vertex 2 has a non-finite"),
    ("hugecount.ply", PLY_ASCII.format("99999999999999999999", 1) + SQUARE + "3 0 1 2\n",
     "truncated"),
    ("negativecount.ply", PLY_ASCII.format(-3, 1) + SQUARE + "3 0 1 2\n", "header line 4"),
    ("scalarface.ply", PLY_ASCII.replace("list uchar int", "int").format(3, 1)
     + "0 0 0\n1 0 0\n0 1 0\n2\n", "not a list property"),
    ("listvertex.ply", PLY_ASCII.replace("float x", "list uchar float x").format(3, 1)
     + "1 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 1 2\n", "no vertex positions"),
    ("negativebinary.ply", binary_ply_with(b"\xff\xff\xff\xff"), "bad list length -1"),
    ("hugebinary.ply", binary_ply_with(struct.pack("<i3f", 3, 0, 1, 1e30), "float"),
     "face 0 references vertex 1e+30 but the file has 3 vertices"),
    ("nanbinary.ply", binary_ply_with(struct.pack("<i3f", 3, 0, 1, np.nan), "float"),
     "face 0 has vertex index nan"),
    # OFF
    ("notoff.off", "PLY\n3 1 0\n", "not an OFF file"),
    ("counts.off", "OFF\nthree one\n", "bad vertex and face counts"),
    ("truncated.off", "OFF\n4 2 0\n" + SQUARE + "3 0 1 2\n", "truncated"),
    ("extra.off", "OFF\n4 1 0\n" + SQUARE + "3 0 1 2\n3 0 2 3\n", "line 8: data after"),
    ("range.off", "OFF\n4 2 0\n" + SQUARE + "3 0 1 2\n4 0 1 2 7\n",
     "range.off, line 8: face 1 references vertex 7 but the file has 4 vertices"),
    ("nan.off", "OFF\n4 1 0\n0 0 0\n1 0 inf\n1 1 0\n0 1 0\n3 0 1 2\n", "line 4: vertex 1"),
    ("badvertex.off", "OFF\n4 1 0\n0 0 0\n1 0\n1 1 0\n0 1 0\n3 0 1 2\n", "3 coordinates"),
    ("noface.off", "OFF\n4 0 0\n" + SQUARE, "no faces"),
    ("edge.off", "OFF\n4 1 0\n" + SQUARE + "2 0 1\n", "at least 3 corners"),
    ("fourd.off", "4OFF\n1 1 0\n0 0 0 0\n", "not 3-D"),
    ("hugeindex.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n",
     "line 6: face 0 references vertex 99999999999999999999 but the file has 3 vertices"),
    ("negative.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
     "line 6: face 0 references vertex -1"),
    ("negativecount.off", "OFF\n3 -1 0\n0 0 0\n1 0 0\n0 1 0\n", "negative vertex or face count"),
    ("hugecount.off", "OFF\n3 99999999999999999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
     "truncated"),
    ("hugecorners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n99999999999999999999 0 1 2\n",
     "line 6: the face announces 99999999999999999999 corners but lists 3"),
    ("hugecoordinate.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 -1e999 0\n3 0 1 2\n",
     "line 5: vertex 2 has a non-finite"),
    # STL
    ("text.stl", "solid x\nfacet normal 0 0 1\n",
     "text.stl, line 3: the file ends in the facet begun on line 2 where 'outer loop' should"),
    ("binary.stl", b"\0" * 80 + struct.pack("<I", 5) + b"\0" * 60, "no triangles could be read"),
    # unknown formats
    ("mesh.xyz", "1 2 3\n", "unknown mesh format '.xyz'"),
    ("noextension", "v 0 0 0\n", "unknown mesh format '(no extension)'"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "content", "message"), BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_files_are_rejected_naming_the_file_and_the_problem(tmp_path, name, content, message):
    path = write(tmp_path / name, content)
    with pytest.raises(MeshFileError) as info:
        load_mesh(path)
    assert str(info.value).startswith(name)
    assert message in str(info.value)


# -- the OBJ reader: whole arrays, statement by statement where they cannot do ----------------
def outcome(read, content: bytes, name: str = "t.obj"):
    """What a reader makes of ``content``: the mesh's arrays, or the error message."""
    try:
        mesh = read(content, name)
    except MeshFileError as exc:
        return str(exc)
    uv = None if mesh.uv is None else (mesh.uv.view(np.uint64).tolist(), mesh.uv_faces.tolist())
    return mesh.vertices.view(np.uint64).tolist(), mesh.faces.tolist(), uv


TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
REGULAR_OBJ = [
    TRI + "f 1 2 3\n",
    "# c\n\n" + TRI + "vn 0 0 1\ng a\ns 1\nusemtl m\nf 1//1 2//1 3//1\n",
    TRI + "v 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1/1 2/2/1 3/3/1\nf 2/2/1 4/1/1 3/3/1\n",
    TRI + "v 1 1 0\nvt 0\nvt 1\nvt 0.5\nf 1/1 2/2 3/3 4/1\n",  # 1-value vt, a quad
    TRI + "v 1 1 0\nv 2 2 0\nf 1 2 3\nf 1 2 4 3\nf -1 -2 -3 -4 -5\n",  # mixed sizes, relative
    "f 1 2 3\n" + TRI + "v 1e-300 -2.5E+10 .5\nf 4 2 3\n",  # forward reference
    "v 0\t0  0\nv 1 0\t0 \nv 0 1 0\n#### a # comment\nf  1\t2   3  \n",  # tabs, spaces
    TRI.replace("\n", "\r\n") + "f 1 2 3\r\n",
    "\ufeff" + TRI + "f 1 2 3",  # a BOM, no final line end
    TRI + "vt 0 0\nvt 1 0 0\nf 1/1 2/2 3/1\nf 3/-1 2/-2 1/-1\n",
    TRI + "v 1 2 3 0.5 0.5 0.5\nf 1 2 4\n",  # w or colours after x y z
    TRI + "g a\nusemtl a\nf 1 2 3\ng b\nusemtl b\nf 1 3 2\nf 2 1 3\n",  # face groups
    TRI + "f 1 2 3\nv 1 1 1\nf 1 2 -1\nv 2 2 2\nf -1 -2 -3\n",  # interleaved, relative
    "vt 0 0\nv 0 0 0\nvt 1 0\nv 1 0 0\nv 0 1 0\nvt 0 1\nf 1/-1 2/-2 3/-3\n",
]
IRREGULAR_OBJ = [  # each is read by the strict reader (accepted or refused the same way)
    TRI + "f 1 2 3 # a comment\n",
    TRI + "f 1 2 3\n #\n",
    TRI + "v 1 2 v3\nf 1 2 3\n",
    TRI + "v 1 2 3 x\nf 1 2 4\n",  # extra non-numbers after x y z: accepted by both
    TRI + "v 1 2\nv 1 2 3 4\nf 1 2 3\n",
    TRI + "v\t1 2 3\nf\t1 2 3\n",
    TRI + "v 0 nan 0\nf 1 2 3\n",
    TRI + "v 0 1e999 0\nf 1 2 3\n",
    TRI + "vt nan 0\nf 1/1 2/1 3/1\n",
    TRI + "vt 0\nvt 1 0\nf 1/1 2/2 3/1\n",
    TRI + "vt 0 0\nf 1/1 2 3/1\n",
    TRI + "vt 0 0\nf 1/1/1 2 3/1/1/1/1\n",
    TRI + "vt 0 0\nf 1//1 2/1 3//1\n",
    TRI + "vt 0 0\nf 1/ 2/ 3/\n",
    TRI + "f 1 2 3\nf 1 2 3 -0\n",
    TRI + "f 1 2 0\n",
    TRI + "f 1 2 99999999999999999999\n",
    TRI + "f 1 2 -99999999999999999999\n",
    TRI + "f 1 2 -4\n",
    TRI + "f 1 2 4\n",
    TRI + "f +1 +2 +3\n",
    TRI + "f 1 2\n",
    TRI + "f 1 2 3.0\n",
    TRI + "f 1 2 1e0\n",
    TRI + "vt 0 0\nf 1/2 2/1 3/1\n",
    TRI + "vt 0 0\nf 1/-2 2/1 3/1\n",
    TRI + "f 1 2 3\x00\n",
    TRI + "f 1 2 3\rf 1 3 2\n",
    TRI + "v 1_0 2 3\nf 1 2 4\n",
    TRI + "vv 1 2 3\nf 1 2 3\n",
    TRI + "fo 1 2 3\n",
    TRI,
    "vt 0 0\nf 1 2 3\n",
]


#: What the OBJ reader makes of each of them, recorded when a line-by-line reader (the reference
#: the whole-array one was held to) read every file.
OBJ_OUTCOMES = json.loads((Path(__file__).parent / "obj_outcomes.json").read_text())


@pytest.mark.parametrize("content", REGULAR_OBJ + IRREGULAR_OBJ)
def test_obj_files_are_read_as_the_line_by_line_reference_read_them(content):
    found = outcome(obj.read_obj, content.encode("utf-8"))
    assert json.loads(json.dumps(found)) == OBJ_OUTCOMES[content]


def _read_statement_by_statement(statements, *args):
    for _ in statements:
        raise AssertionError("a regular OBJ file was read statement by statement")


@pytest.mark.parametrize("content", REGULAR_OBJ)
def test_regular_obj_files_are_read_as_whole_arrays(content, monkeypatch):
    monkeypatch.setattr(obj, "_each", _read_statement_by_statement)
    assert obj.read_obj(content.encode("utf-8"), "t.obj") is not None


def test_every_listed_obj_mesh_is_read_as_whole_arrays(listed, monkeypatch):
    path, _ = listed
    monkeypatch.setattr(obj, "_each", _read_statement_by_statement)
    assert len(obj.read_obj(path.read_bytes(), path.name).faces)


ASCII_PLY_FILES = [(n, c) for n, c, _ in BAD_FILES if n.endswith(".ply")] + [
    ("square.ply", PLY_ASCII.format(5, 2) + SQUARE + "0 0 1\n4 0 1 2 3\n5 0 1 2 3 4\n"),
    ("triangle.ply", PLY_ASCII.format(3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
]


@pytest.mark.parametrize(("name", "content"), ASCII_PLY_FILES, ids=[n for n, _ in ASCII_PLY_FILES])
def test_ascii_ply_fast_parsing_agrees_with_token_by_token(tmp_path, monkeypatch, name, content):
    path = write(tmp_path / name, content)
    data = path.read_bytes()
    fast = outcome(ply.read_ply, data, name)

    def refuse(*_args, **_kwargs):
        raise ValueError("string or file could not be read to its end")

    monkeypatch.setattr(text.np, "fromstring", refuse)  # the token-by-token path
    assert outcome(ply.read_ply, data, name) == fast


@pytest.mark.parametrize("cut", [1, 5, 13, -1])
def test_truncated_or_padded_binary_ply_is_rejected(tmp_path, cut):
    path = write(tmp_path / "cut.ply", cut_binary_ply(tmp_path, cut))
    with pytest.raises(MeshFileError, match=r"cut\.ply: .*(truncated|do not match)"):
        load_mesh(path)


def test_truncated_binary_stl_is_rejected(made_textured, tmp_path):
    save_mesh(load_mesh(made_textured.path), tmp_path / "m.stl")
    data = (tmp_path / "m.stl").read_bytes()
    path = write(tmp_path / "cut.stl", data[:-10])
    with pytest.raises(MeshFileError, match=r"cut\.stl: no triangles could be read"):
        load_mesh(path)


def ascii_stl(mesh: MeshData) -> str:
    """The mesh as an ASCII STL, written here (one statement a line, as exporters do)."""
    facets = []
    for corners in mesh.vertices[mesh.faces].tolist():
        rows = "".join(f"      vertex {x!r} {y!r} {z!r}\n" for x, y, z in corners)
        facets.append(f"  facet normal 0 0 1\n    outer loop\n{rows}    endloop\n  endfacet\n")
    return "solid made\n" + "".join(facets) + "endsolid made\n"


def test_truncated_ascii_stl_is_refused_naming_the_line(made_textured, tmp_path):
    mesh = load_mesh(made_textured.path)
    mesh = MeshData(mesh.vertices, mesh.faces[:80])
    lines = ascii_stl(mesh).splitlines(keepends=True)
    assert len(lines) == 2 + 7 * 80
    whole = load_mesh(write(tmp_path / "whole.stl", "".join(lines)))
    assert len(whole.faces) == 80
    # Cut after 53 whole facets plus each part of the 54th: the file ends inside that facet.
    begun = 2 + 7 * 53
    for kept in range(1, 7):
        path = write(tmp_path / "cut.stl", "".join(lines[: begun - 1 + kept]))
        with pytest.raises(
            MeshFileError,
            match=rf"^cut\.stl, line {begun + kept}: the file ends in the facet "
            rf"begun on line {begun} where '.*' should follow \(a truncated ASCII STL\)",
        ):
            load_mesh(path)
    # Cut in the middle of a vertex line: that line is named.
    cut = "".join(lines[: begun + 2]) + lines[begun + 2][:15]
    with pytest.raises(MeshFileError, match=rf"^cut\.stl, line {begun + 3}: .*'vertex x y z'"):
        load_mesh(write(tmp_path / "cut.stl", cut))
    # All facets whole but no endsolid: refused too, at the end of the file.
    path = write(tmp_path / "noend.stl", "".join(lines[:-1]))
    with pytest.raises(
        MeshFileError,
        match=rf"^noend\.stl, line {len(lines)}: the file ends where 'facet' or 'endsolid' should",
    ):
        load_mesh(path)
    # A facet that misses a corner, in the middle of the file.
    del lines[begun + 3]
    with pytest.raises(
        MeshFileError,
        match=rf"^gap\.stl, line {begun + 4}: expected 'vertex x y z' in the facet begun on "
        rf"line {begun}, found 'endloop'",
    ):
        load_mesh(write(tmp_path / "gap.stl", "".join(lines)))


def test_ascii_stl_numbers_found_by_fuzzing(tmp_path):
    """A non-finite vertex names its line (not only the safety net's vertex number); digits
    grouped by '_' read as ASCII PLY reads them (the search for a bad number found none)."""
    facet = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex {} 0 0\n"
    facet += "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n"
    with pytest.raises(MeshFileError, match=r"^inf\.stl, line 5: the vertex '1e999 0 0' is not"):
        load_mesh(write(tmp_path / "inf.stl", facet.format("1e999")))
    assert load_mesh(write(tmp_path / "u.stl", facet.format("1_0"))).vertices[1].tolist() == [
        10,
        0,
        0,
    ]


@pytest.mark.parametrize(
    ("name", "content"),
    [
        ("bom.obj", "\ufeffv 1 2 3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("crlf.obj", "v 1 2 3\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n"),
        ("cr.obj", "v 1 2 3\rv 1 0 0\rv 0 1 0\rf 1 2 3\r"),
        ("bom.off", "\ufeffOFF\n3 1 0\n1 2 3\n1 0 0\n0 1 0\n3 0 1 2\n"),
        ("cr.off", "OFF\r3 1 0\r1 2 3\r1 0 0\r0 1 0\r3 0 1 2\r"),
        ("bom.ply", "\ufeff" + PLY_ASCII.format(3, 1) + "1 2 3\n1 0 0\n0 1 0\n3 0 1 2\n"),
    ],
)
def test_byte_order_marks_and_old_line_ends_lose_nothing(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content.encode("utf-8"))
    mesh = load_mesh(path)
    assert mesh.vertices.tolist() == [[1, 2, 3], [1, 0, 0], [0, 1, 0]]
    assert mesh.faces.tolist() == [[0, 1, 2]]


def test_missing_file_and_folder(tmp_path):
    with pytest.raises(MeshFileError, match=r"absent\.obj: no such file"):
        load_mesh(tmp_path / "absent.obj")
    (tmp_path / "folder.obj").mkdir()
    with pytest.raises(MeshFileError, match=r"folder\.obj: not a file"):
        load_mesh(tmp_path / "folder.obj")


def test_mesh_file_error_is_a_value_error():
    assert issubclass(MeshFileError, ValueError)


# -- saving ------------------------------------------------------------------------------------
@pytest.fixture
def saved(made_textured, tmp_path):
    """A good OBJ on disk, its bytes, and the mesh."""
    mesh = load_mesh(made_textured.path)
    target = tmp_path / "good.obj"
    save_mesh(mesh, target)
    return target, target.read_bytes(), mesh


def assert_untouched(target: Path, original: bytes) -> None:
    assert target.read_bytes() == original
    assert sorted(os.listdir(target.parent)) == [target.name]  # no temporary file left


def test_unsaveable_meshes_are_refused_before_writing(saved):
    target, original, mesh = saved
    bad = mesh.copy()
    bad.vertices[3, 1] = np.nan
    with pytest.raises(MeshFileError, match=r"good\.obj: vertex 3 has a non-finite"):
        save_mesh(bad, target)
    bad = mesh.copy()
    bad.faces[7, 2] = len(mesh.vertices)
    with pytest.raises(MeshFileError, match=f"face 7 references vertex {len(mesh.vertices)}"):
        save_mesh(bad, target)
    bad = mesh.copy()
    bad.uv_faces = bad.uv_faces[:-1]
    with pytest.raises(MeshFileError, match="uv_faces"):
        save_mesh(bad, target)
    bad = MeshData(np.zeros((3, 3)), np.zeros((0, 3)))
    with pytest.raises(MeshFileError, match="no faces"):
        save_mesh(bad, target)
    with pytest.raises(MeshFileError, match=r"cannot save as '\.xyz'"):
        save_mesh(mesh, target.with_suffix(".xyz"))
    assert_untouched(target, original)


def test_os_error_mid_write_leaves_the_old_file(saved, monkeypatch):
    target, original, mesh = saved

    def half_then_disk_full(mesh, out):
        out.write(b"v 1 2 3\n" * 100)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(obj, "write_obj", half_then_disk_full)
    with pytest.raises(MeshFileError, match=r"good\.obj: cannot write \(No space left"):
        save_mesh(mesh, target)
    assert_untouched(target, original)


class Interrupted(BaseException):
    """Stands for KeyboardInterrupt without disturbing pytest."""


@pytest.mark.parametrize("error", [RuntimeError("bug"), Interrupted()])
def test_any_exception_mid_write_leaves_the_old_file(saved, monkeypatch, error):
    target, original, mesh = saved

    def explode(mesh, out):
        out.write(b"partial")
        raise error

    monkeypatch.setattr(obj, "write_obj", explode)
    with pytest.raises(type(error)):
        save_mesh(mesh, target)
    assert_untouched(target, original)


def test_failed_rename_leaves_the_old_file(saved, monkeypatch):
    target, original, mesh = saved

    def refuse(*_args):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(atomic.os, "replace", refuse)
    with pytest.raises(MeshFileError, match="Permission denied"):
        save_mesh(mesh, target)
    assert_untouched(target, original)


def test_save_into_a_missing_folder(tmp_path):
    with pytest.raises(MeshFileError, match=r"out\.ply: the folder .* does not exist"):
        save_mesh(TRIANGLE, tmp_path / "nowhere" / "out.ply")


def test_save_keeps_permissions_and_symlinks(tmp_path):
    target = tmp_path / "mesh.off"
    save_mesh(TRIANGLE, target)
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask  # a normal new file
    target.chmod(0o640)
    save_mesh(TRIANGLE, target)
    assert target.stat().st_mode & 0o777 == 0o640
    link = tmp_path / "link.off"
    link.symlink_to(target.name)
    moved = TRIANGLE.copy()
    moved.vertices += 1
    save_mesh(moved, link)
    assert link.is_symlink()
    assert np.array_equal(load_mesh(target).vertices, moved.vertices)


def test_save_replaces_an_existing_file_completely(made_textured, tmp_path):
    target = tmp_path / "m.ply"
    save_mesh(load_mesh(made_textured.path), target)
    save_mesh(TRIANGLE, target)
    assert np.array_equal(load_mesh(target).faces, [[0, 1, 2]])


def test_write_bytes_atomic_replaces_keeps_permissions_and_names_failures(tmp_path, monkeypatch):
    target = tmp_path / "shot.png"
    target.write_bytes(b"old picture, longer than the new one")
    target.chmod(0o640)
    atomic.write_bytes_atomic(target, b"\x89PNG new")
    assert target.read_bytes() == b"\x89PNG new"
    assert target.stat().st_mode & 0o777 == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["shot.png"]  # no temporary file left

    def refuse(*_args):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(atomic.os, "replace", refuse)
    with pytest.raises(MeshFileError, match=r"shot\.png: cannot write \(Permission denied"):
        atomic.write_bytes_atomic(target, b"lost")
    assert target.read_bytes() == b"\x89PNG new"
    assert [p.name for p in tmp_path.iterdir()] == ["shot.png"]
    monkeypatch.undo()
    with pytest.raises(MeshFileError, match="does not exist"):
        atomic.write_bytes_atomic(tmp_path / "nowhere" / "shot.png", b"x")


def test_uppercase_extensions(tmp_path):
    save_mesh(TRIANGLE, tmp_path / "T.PLY")
    assert np.array_equal(load_mesh(tmp_path / "T.PLY").vertices, TRIANGLE.vertices)


# -- MeshData ----------------------------------------------------------------------------------
def test_mesh_data_copy_is_deep_and_arrays_are_coerced():
    mesh = MeshData([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], uv=[[0, 0]], uv_faces=[[0] * 3])
    assert mesh.vertices.dtype == np.float64 and mesh.faces.dtype == np.int64
    clone = mesh.copy()
    clone.vertices[0, 0] = 1
    clone.uv[0, 0] = 1
    clone.uv_faces[0, 0] = -1
    assert mesh.vertices[0, 0] == 0 and mesh.uv[0, 0] == 0 and mesh.uv_faces[0, 0] == 0
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        MeshData(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(ValueError, match="together"):
        MeshData(np.zeros((3, 3)), [[0, 1, 2]], uv=np.zeros((1, 2)))
