"""What other programs write and other readers accept: OBJ continuation lines, the DOS end-of-
file byte, OFF counts glued to the keyword, PLY triangle strips, PLY lists of mixed lengths
(binary and ASCII, read by the compiled record walker), clear list-length messages, and the same
number parsing under numpy 1.26 as under numpy 2."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
from mesh_io_models import U_SHAPE, edges_used_once, triangle_area

from gogreen_core.mesh.mesh_io import MeshFileError, load_mesh, obj, save_mesh
from gogreen_core.mesh.mesh_io.obj import read_obj
from gogreen_core.mesh.mesh_io.text import parse_numbers


def outcome(read, content: bytes, name: str = "t.obj"):
    """What a reader makes of ``content``: the mesh's arrays, or the error message."""
    try:
        mesh = read(content, name)
    except MeshFileError as exc:
        return str(exc)
    uv = None if mesh.uv is None else (mesh.uv.tolist(), mesh.uv_faces.tolist())
    return mesh.vertices.tolist(), mesh.faces.tolist(), uv


# A wall with a square hole as Rhino writes it: faces through edge midpoints (corners in a
# row), concave faces, and long faces continued on the next line by a backslash.
WALL = (
    "# Rhino\n\nmtllib 00.mtl\nusemtl \n"
    + "".join(f"v {x} {y} 0\n" for x, y in [(0, 0), (10, 0), (10, 10), (0, 10)])
    + "".join(f"v {x} {y} 0\n" for x, y in [(3, 3), (7, 3), (7, 7), (3, 7)])
    + "".join(f"v {x} {y} 0\n" for x, y in [(5, 0), (10, 5), (5, 10), (0, 5)])
    + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    + "f 1/1 9/2 2/2 10/3 6/3 5/4 \\\n  8/4 12/1\n"  # around the hole's lower-left
    + "f 10/1 3/2 11/3 \\\n7/4 6/1\n"
    + "f 11/1 4/2 12/3 8/4 7/1\n"
)
WALL_AREA = 100.0 - 16.0


def test_continued_lines_are_joined_like_the_specification_says(tmp_path: Path, monkeypatch):
    data = WALL.encode()
    (tmp_path / "wall.obj").write_bytes(data)
    mesh = load_mesh(tmp_path / "wall.obj")
    assert triangle_area(mesh.vertices, mesh.faces) == WALL_AREA
    assert len(mesh.faces) == (8 - 2) + (5 - 2) + (5 - 2)
    joined = data.replace(b"\\\n  ", b"").replace(b"\\\n", b"")
    assert outcome(read_obj, data) == outcome(read_obj, joined)
    monkeypatch.setattr(obj, "_each", lambda found, *_: [pytest.fail("one by one") for _ in found])
    assert outcome(read_obj, data) == outcome(read_obj, joined)  # as whole arrays


def test_line_numbers_count_the_continued_lines(tmp_path: Path):
    data = b"v 0 0 0\nv 1 0 0\nf 1 \\\n 2 \\\n 3\nv 0 1 0\nf 1 2 7\n"
    with pytest.raises(MeshFileError, match=r"t\.obj, line 7: face 2 references vertex 7"):
        read_obj(data, "t.obj")
    with pytest.raises(MeshFileError, match=r"line 3: bad vertex index 'x'"):
        read_obj(b"v 0 0 0\nv 1 0 0\nf 1 2 \\\n x\n", "t.obj")


def test_a_comment_never_continues(tmp_path: Path):
    """A Windows path at the end of a comment must not swallow the next line."""
    data = b"# saved to C:\\models\\\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3  # done \\\nf 1 3 2\n"
    mesh = read_obj(data, "t.obj")
    assert len(mesh.vertices) == 3 and mesh.faces.tolist() == [[0, 1, 2], [0, 2, 1]]


TRIANGLE_FILES = {
    "t.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "t.off": "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "t.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "t.stl": "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
    "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
}


@pytest.mark.parametrize("name", TRIANGLE_FILES)
@pytest.mark.parametrize("ending", [b"\x1a", b"\r\n\x1a", b"\x1a\r\n", b"\n\x1a\n"])
def test_the_dos_end_of_file_byte_is_accepted(tmp_path: Path, name, ending):
    text = TRIANGLE_FILES[name].encode().replace(b"\n", b"\r\n")
    path = tmp_path / name
    path.write_bytes(text.rstrip() + ending)
    mesh = load_mesh(path)
    assert mesh.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    assert mesh.faces.tolist() == [[0, 1, 2]]


def test_a_dos_end_of_file_byte_after_binary_ply_data(tmp_path: Path):
    (tmp_path / "t.off").write_text(TRIANGLE_FILES["t.off"])
    path = tmp_path / "b.ply"
    save_mesh(load_mesh(tmp_path / "t.off"), path)
    path.write_bytes(path.read_bytes() + b"\x1a")
    assert load_mesh(path).faces.tolist() == [[0, 1, 2]]


def test_the_dos_byte_inside_a_file_is_still_refused(tmp_path: Path):
    path = tmp_path / "mid.obj"
    path.write_bytes(b"v 0 0 0\n\x1a\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(MeshFileError, match="line 2: unknown statement"):
        load_mesh(path)


CUBE_OFF8 = "OFF8 6 12\n" + "".join(
    f"{x} {y} {z}\n" for x in (0, 1) for y in (0, 1) for z in (0, 1)
) + "4 0 1 3 2\n4 4 6 7 5\n4 0 4 5 1\n4 2 3 7 6\n4 0 2 6 4\n4 1 5 7 3\n"  # fmt: skip


@pytest.mark.parametrize("keyword", ["OFF8 6 12", "COFF8 6 12", "OFF 8 6 12", "OFF\n8 6 12"])
def test_off_counts_may_be_glued_to_the_keyword(tmp_path: Path, keyword):
    text = CUBE_OFF8.replace("OFF8 6 12", keyword)
    if keyword.startswith("COFF"):  # colours after each vertex
        lines = text.split("\n")
        text = "\n".join([lines[0]] + [v + " 1 0 0 1" for v in lines[1:9]] + lines[9:])
    path = tmp_path / "cube.off"
    path.write_text(text)
    mesh = load_mesh(path)
    assert len(mesh.vertices) == 8 and len(mesh.faces) == 12
    assert triangle_area(mesh.vertices, mesh.faces) == 6.0 and edges_used_once(mesh.faces) == 0


@pytest.mark.parametrize("bad", ["OFFx 6 12", "OFF8x 6 12", "NOFFOFF 1 1"])
def test_off_keywords_that_are_not_off_are_refused(tmp_path: Path, bad):
    path = tmp_path / "bad.off"
    path.write_text(CUBE_OFF8.replace("OFF8 6 12", bad))
    with pytest.raises(MeshFileError, match="not an OFF file"):
        load_mesh(path)


def strips_ply(strips: list[list[int]], faces: list[list[int]] | None = None) -> str:
    points = [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)]
    header = (
        "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
        "property float z\n"
        + (f"element face {len(faces)}\nproperty list uchar int vertex_indices\n" if faces else "")
        + f"element tristrips {len(strips)}\nproperty list int int vertex_indices\nend_header\n"
    )
    rows = "".join(f"{x} {y} 0\n" for x, y in points)
    rows += "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces or [])
    return header + rows + "".join(f"{len(s)} " + " ".join(map(str, s)) + "\n" for s in strips)


@pytest.mark.parametrize(
    ("strips", "faces", "expected"),
    [
        ([[0, 1, 2, 3, 4, 5]], None, [[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5]]),
        ([[0, 1, 2, 3, -1, 2, 3, 4, 5]], None, [[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5]]),
        ([[0, 1, 2, 3], [2, 3, 4, 5]], None, [[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5]]),
        ([[0, 1, 2, 2, 3, 4]], None, [[0, 1, 2], [3, 2, 4]]),  # degenerate ones dropped
        ([[2, 3, 4, 5]], [[0, 1, 3, 2]], [[0, 1, 3], [0, 3, 2], [2, 3, 4], [4, 3, 5]]),
    ],
)
def test_ply_triangle_strips(tmp_path: Path, strips, faces, expected):
    path = tmp_path / "strips.ply"
    path.write_text(strips_ply(strips, faces))
    mesh = load_mesh(path)
    assert mesh.faces.tolist() == expected  # every other triangle of a strip flipped


@pytest.mark.parametrize(
    ("strips", "message"),
    [
        ([[0, 1, 9]], "tristrip 0 references vertex 9 but the file has 6 vertices"),
        ([[0, 1, 2], [0, -2, 3]], "tristrip 1 references vertex -2"),
        ([[0, 1]], "no faces"),
    ],
)
def test_bad_triangle_strips_are_refused(tmp_path: Path, strips, message):
    path = tmp_path / "strips.ply"
    path.write_text(strips_ply(strips))
    with pytest.raises(MeshFileError, match=message):
        load_mesh(path)


# -- PLY lists of mixed lengths ------------------------------------------------------------------
def mixed_polygons(rng: np.random.Generator, n_vertices: int, count: int) -> list[list[int]]:
    return [list(rng.choice(n_vertices, int(k), replace=False)) for k in rng.choice(
        [3, 4, 5, 4, 3, 7], count)]  # fmt: skip


@pytest.mark.parametrize("endian", ["<", ">"])
@pytest.mark.parametrize(("count_type", "index_type"), [("B", "I"), ("H", "i"), ("i", "H")])
def test_binary_ply_lists_of_mixed_lengths(tmp_path: Path, endian, count_type, index_type):
    """Records with a scalar before and after the list (flags, a colour), several list
    lengths: every face as a record-by-record reading gives it."""
    rng = np.random.default_rng(7)
    vertices = rng.normal(size=(40, 3)).astype(np.float32)
    polygons = mixed_polygons(rng, 40, 300)
    types = {"B": "uchar", "H": "ushort", "i": "int", "I": "uint"}
    header = (
        f"ply\nformat binary_{'little' if endian == '<' else 'big'}_endian 1.0\n"
        "element vertex 40\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 300\nproperty short flags\n"
        f"property list {types[count_type]} {types[index_type]} vertex_indices\n"
        "property uchar red\nend_header\n"
    )
    body = vertices.astype(endian + "f4").tobytes()
    for k, p in enumerate(polygons):
        body += struct.pack(f"{endian}h{count_type}{len(p)}{index_type}B", -k, len(p), *p, k % 256)
    path = tmp_path / "mixed.ply"
    path.write_bytes(header.encode() + body)
    mesh = load_mesh(path)
    expected = [[p[0], p[j], p[j + 1]] for p in polygons for j in range(1, len(p) - 1)]
    # Random polygons are twisted in space: compare the corner sets of each polygon.
    assert len(mesh.faces) == len(expected)
    start = 0
    for p in polygons:
        got = mesh.faces[start : start + len(p) - 2]
        assert set(got.ravel().tolist()) == set(p)
        start += len(p) - 2
    assert np.array_equal(mesh.vertices, vertices.astype(np.float64))
    for cut in (1, 7):
        path.write_bytes(header.encode() + body[:-cut])
        with pytest.raises(MeshFileError, match="truncated"):
            load_mesh(path)


def test_mixed_binary_lists_keep_the_fans_of_flat_convex_faces(tmp_path: Path):
    """A grid of quads and triangles mixed (flat, convex): the faces are the fans, in order."""
    rng = np.random.default_rng(1)
    grid = np.array([(x, y, 0) for y in range(30) for x in range(30)], dtype=np.float32)
    polygons = []
    for y in range(29):
        for x in range(29):
            a, b, c, d = 30 * y + x, 30 * y + x + 1, 30 * (y + 1) + x + 1, 30 * (y + 1) + x
            polygons += [[a, b, c], [a, c, d]] if rng.random() < 0.5 else [[a, b, c, d]]
    header = (
        "ply\nformat binary_little_endian 1.0\nelement vertex 900\nproperty float x\n"
        f"property float y\nproperty float z\nelement face {len(polygons)}\n"
        "property list uchar uint vertex_indices\nend_header\n"
    )
    body = grid.tobytes() + b"".join(struct.pack(f"<B{len(p)}I", len(p), *p) for p in polygons)
    path = tmp_path / "grid.ply"
    path.write_bytes(header.encode() + body)
    mesh = load_mesh(path)
    expected = [[p[0], p[j], p[j + 1]] for p in polygons for j in range(1, len(p) - 1)]
    assert mesh.faces.tolist() == expected
    assert triangle_area(mesh.vertices, mesh.faces) == 29 * 29


def test_a_negative_list_length_in_a_mixed_binary_ply(tmp_path: Path):
    header = (
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face 2\n"
        "property list int int vertex_indices\nend_header\n"
    )
    body = np.zeros((4, 3), "<f4").tobytes() + struct.pack("<i3i", 3, 0, 1, 2)
    path = tmp_path / "neg.ply"
    path.write_bytes(header.encode() + body + struct.pack("<i", -5) + b"\0" * 16)
    with pytest.raises(MeshFileError, match=r"neg\.ply: bad list length -5 in element 'face'"):
        load_mesh(path)


def test_ascii_ply_lists_of_mixed_lengths(tmp_path: Path):
    rng = np.random.default_rng(3)
    vertices = rng.normal(size=(30, 3))
    polygons = mixed_polygons(rng, 30, 200)
    header = (
        "ply\nformat ascii 1.0\nelement vertex 30\nproperty double x\nproperty double y\n"
        "property double z\nelement face 200\nproperty list uchar int vertex_indices\n"
        "property float quality\nend_header\n"
    )
    rows = "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in vertices.tolist())
    rows += "".join(f"{len(p)} {' '.join(map(str, p))} 0.5\n" for p in polygons)
    path = tmp_path / "mixed.ply"
    path.write_text(header + rows)
    mesh = load_mesh(path)
    assert np.array_equal(mesh.vertices, vertices)
    start = 0
    for p in polygons:
        assert set(mesh.faces[start : start + len(p) - 2].ravel().tolist()) == set(p)
        start += len(p) - 2
    assert start == len(mesh.faces)


# -- list lengths and rows ---------------------------------------------------------------------
PLY_HEADER = (
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
)


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        # Normals written but not declared: the first row says so (not "bad list length 0.6").
        ("0 0 0 0.599829 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n3 0 2 3\n",
         r"line 10: element 'vertex' row 0 has 6 values but the header declares 3 \(x, y, z\): "
         "the row has more values than declared"),
        ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 3\n3 0 2 3\n",
         "line 14: element 'face' row 0 has 5 values but the header declares 4"),
        ("0 0 0\n1 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
         "line 11: element 'vertex' row 1 has 2 values but the header declares 3 .*fewer"),
    ],
)  # fmt: skip
def test_a_row_with_values_the_header_does_not_declare_is_named(tmp_path: Path, rows, message):
    path = tmp_path / "rows.ply"
    path.write_text(PLY_HEADER + rows)
    with pytest.raises(MeshFileError, match=message):
        load_mesh(path)


# -- numpy 1.26 and 2 --------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "dtype"),
    [(b"1 2 x", np.float64), (b"1 2 3.5", np.int64), (b"1e3", np.int64), (b"1_0 2", np.float64),
     (b"0x10", np.float64), (b"1 2\x1c3", np.float64)],
)  # fmt: skip
def test_parse_numbers_refuses_what_it_cannot_read_whole(text, dtype):
    """numpy 2 raises here, numpy 1.26 only warns and returns the numbers before the token: both
    raise ValueError (the test suite runs the mesh tests under both)."""
    with pytest.raises(ValueError, match="could not be read to its end"):
        parse_numbers(text, dtype)


def test_parse_numbers_reads_what_is_whole():
    assert parse_numbers(b" 1\t2\n-3e2 nan ", np.float64)[:3].tolist() == [1, 2, -300]
    assert parse_numbers(b"+1 -0 7", np.int64).tolist() == [1, 0, 7]
    assert parse_numbers(b"", np.float64).tolist() == []


@pytest.mark.parametrize(
    "tail", ["3 0 1 2\n3 0 2 3 garbage\n", "3 0 1 2\n3 0 2 3\n4x\n", "3 0 1 2\n3 0 2 3.5.1\n"]
)
def test_ascii_ply_with_trailing_garbage_is_refused(tmp_path: Path, tail):
    """Under numpy 1.26 these were accepted silently (the parse stopped at the bad token)."""
    path = tmp_path / "garbage.ply"
    path.write_text(PLY_HEADER + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + tail)
    with pytest.raises(MeshFileError, match=r"garbage\.ply: bad number"):
        load_mesh(path)


def test_decimals_are_rounded_correctly_under_any_numpy(tmp_path: Path):
    """Decimals are rounded correctly (like float()), under numpy 1.26 as under 2."""
    lines = [f"v {x}.1 {y}.3 0.7" for x, y in U_SHAPE] + ["f 1 2 3 4 5 6 7 8"]
    path = tmp_path / "u.obj"
    path.write_text("\n".join(lines) + "\n")
    mesh = load_mesh(path)
    assert mesh.vertices[:, 0].tolist() == [float(f"{x}.1") for x, _ in U_SHAPE]
    assert triangle_area(mesh.vertices, mesh.faces) == pytest.approx(5.0, rel=1e-14)


# -- compiled code -----------------------------------------------------------------------------
WARM_UP_CHECK = """
import sys
import numpy as np
from gogreen_core.mesh import mesh_io
from gogreen_core.mesh.mesh_io import ply, polygons, weld

loops = [ply._walk_binary_records, ply._copy_runs,
         polygons._fans, weld._first_equal_rows]
mesh_io.warm_up()
ready = {f: set(f.signatures) for f in loops}
for path in sys.argv[1:]:
    mesh = mesh_io.load_mesh(path)
    mesh_io.save_mesh(mesh, path + ".ply")
new = [(f.__name__, s) for f in loops for s in f.signatures if s not in ready[f]]
print(new)
"""


def test_warm_up_compiles_every_loop_that_loading_runs(tmp_path: Path):
    """After ``warm_up`` (the app runs it off the GUI thread), loading files of every kind
    compiles nothing more: a fresh process lists the compiled signatures."""
    import subprocess
    import sys

    from mesh_io_models import binary_stl, blender_obj, blender_ply, u_prism, uv_sphere

    prism, sphere = u_prism(), uv_sphere()
    files = {
        "a.ply": blender_ply(sphere),
        "b.ply": blender_ply(prism, ascii=True),
        "c.ply": blender_ply(prism, export_uv=False),
        "d.stl": binary_stl(sphere.vertices, sphere.triangles),
        "e.obj": blender_obj({"Prism": prism}).encode(),
        "f.stl": TRIANGLE_FILES["t.stl"].encode(),
    }
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    paths = [str(tmp_path / name) for name in files]
    result = subprocess.run(
        [sys.executable, "-c", WARM_UP_CHECK, *paths], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "[]", result.stdout
