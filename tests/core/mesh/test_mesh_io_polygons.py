"""Polygons of mesh files triangulated by their shape: convex ones by the fan as before, concave
ones without covering their notches, every k-gon as k-2 triangles on all its corners."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from mesh_io_models import U_PRISM_AREA, U_SHAPE, blender_ply, edges_used_once, u_prism
from mesh_io_models import triangle_area as area

from gogreen_core.mesh.mesh_io import load_mesh
from gogreen_core.mesh.mesh_io.polygons import triangulate


def shoelace(polygon: np.ndarray) -> float:
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def signed_areas(points2d: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a = points2d[triangles[:, 1]] - points2d[triangles[:, 0]]
    b = points2d[triangles[:, 2]] - points2d[triangles[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def fan_of(sizes: list[int]) -> np.ndarray:
    start, rows = 0, []
    for k in sizes:
        rows += [[start, start + j, start + j + 1] for j in range(1, k - 1)]
        start += k
    return np.array(rows)


def flat(polygon) -> np.ndarray:
    return np.concatenate([np.asarray(polygon, dtype=np.float64), np.zeros((len(polygon), 1))], 1)


def rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


@pytest.mark.parametrize("shift", range(8))
def test_a_concave_u_keeps_its_area_from_any_first_corner(shift):
    points = flat(U_SHAPE)
    corners = np.roll(np.arange(8), -shift)
    triangles = corners[triangulate(points, corners, np.array([8]))]
    assert len(triangles) == 6 and set(triangles.ravel()) == set(range(8))
    assert area(points, triangles) == 5.0
    assert (signed_areas(points[:, :2], triangles) >= 0).all()  # none turned over


def test_convex_polygons_keep_the_fan_of_the_file_order_bit_for_bit():
    rng = np.random.default_rng(3)
    sizes = [3, 4, 5, 8, 4, 3, 12]
    polygons = []
    for k in sizes:  # convex: points on an ellipse, tilted in space, slightly bumpy
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
        ring = np.stack([2 * np.cos(angles), np.sin(angles), 1e-3 * rng.normal(size=k)], 1)
        polygons.append(ring @ rotation(k).T + rng.normal(size=3))
    points = np.concatenate(polygons)
    corners = rng.permutation(len(points))  # any vertex numbering
    positions = np.concatenate(polygons)[np.argsort(corners)]
    triangles = triangulate(positions, corners, np.array(sizes))
    assert np.array_equal(triangles, fan_of(sizes))
    assert triangles.dtype == np.int64


def test_a_nearly_straight_corner_keeps_the_fan():
    """Three corners in a row (up to rounding) do not make a polygon concave."""
    square = flat([(0, 0), (0.3, 0), (0.6, 0), (0.6, 0.6), (0, 0.6)])
    square[1, 1] = 1e-17  # a hair inside: the fan's first triangle turns over by 3e-17 rad
    assert np.array_equal(triangulate(square, np.arange(5), np.array([5])), fan_of([5]))


@pytest.mark.parametrize("seed", range(20))
def test_random_star_shaped_polygons_are_covered_exactly(seed):
    """Polygons with many reflex corners, in a random plane: k-2 triangles, all turning the
    polygon's way, using every corner, and the polygon's area (shoelace) to rounding."""
    rng = np.random.default_rng(seed)
    k = int(rng.integers(5, 60))
    angles = np.sort(rng.uniform(0, 2 * np.pi, k))
    radii = rng.uniform(0.2, 1.0, k)
    polygon2d = np.stack([radii * np.cos(angles), radii * np.sin(angles)], 1)
    turn = rotation(seed)
    points = flat(polygon2d) @ turn.T + [5.0, -3.0, 2.0]
    triangles = triangulate(points, np.arange(k), np.array([k]))
    assert len(triangles) == k - 2 and set(triangles.ravel()) == set(range(k))
    local = (points - [5.0, -3.0, 2.0]) @ turn  # back to the polygon's plane
    assert (signed_areas(local[:, :2], triangles) > -1e-12).all()
    assert area(points, triangles) == pytest.approx(shoelace(polygon2d), rel=1e-12)


def test_corners_in_a_row_and_repeated_corners_stay_connected():
    """Ear clipping drops corners on a straight edge (and repeated ones); they are put back,
    so a neighbour that uses such a corner stays connected: Rhino's wall with a hole writes
    squares with their edge midpoints as corners, and concave ones."""
    notched = flat([(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2), (0, 1)])  # an L
    triangles = triangulate(notched, np.arange(8), np.array([8]))
    assert len(triangles) == 6 and set(triangles.ravel()) == set(range(8))
    assert area(notched, triangles) == 3.0
    edges = {
        tuple(sorted(e)) for t in triangles.tolist() for e in zip(t, t[1:] + t[:1], strict=True)
    }
    assert all(tuple(sorted((i, (i + 1) % 8))) in edges for i in range(8))  # the outline kept
    repeated = flat([(0, 0), (2, 0), (2, 0), (2, 2), (1, 1), (0, 2)])  # concave, corner 2 twice
    triangles = triangulate(repeated, np.arange(6), np.array([6]))
    assert len(triangles) == 4 and set(triangles.ravel()) == set(range(6))
    assert area(repeated, triangles) == 3.0


def test_twisted_polygons_fall_back_to_the_fan_with_their_corners():
    bow_tie = flat([(0, 0), (1, 1), (1, 0), (0, 1)])  # self-intersecting: no triangulation
    triangles = triangulate(bow_tie, np.arange(4), np.array([4]))
    assert len(triangles) == 2 and set(triangles.ravel()) == set(range(4))
    line = flat([(0, 0), (1, 0), (2, 0), (3, 0)])  # no area at all
    assert np.array_equal(triangulate(line, np.arange(4), np.array([4])), fan_of([4]))


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".off", "ascii.ply"])
def test_a_concave_prism_loads_with_its_area_and_closed(tmp_path: Path, suffix):
    prism = u_prism()
    vertices, polygons = prism.vertices, prism.polygons
    rows = "".join(f"{x} {y} {z}\n" for x, y, z in vertices.tolist())
    lists = "".join(f"{len(p)} " + " ".join(map(str, p)) + "\n" for p in polygons)
    files = {
        ".obj": "".join("v " + r for r in rows.splitlines(True))
        + "".join("f " + " ".join(str(i + 1) for i in p) + "\n" for p in polygons),
        ".off": f"OFF\n{len(vertices)} {len(polygons)} 0\n" + rows + lists,
        ".ply": blender_ply(prism, export_uv=False),
        "ascii.ply": blender_ply(prism, ascii=True, export_uv=False),
    }
    path = tmp_path / ("prism" + suffix.removeprefix("ascii"))
    data = files[suffix]
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    mesh = load_mesh(path)
    assert area(mesh.vertices, mesh.faces) == U_PRISM_AREA
    assert edges_used_once(mesh.faces) == 0
    assert len(mesh.faces) == sum(len(p) - 2 for p in polygons)
    sides = mesh.faces[12:]  # the convex side quads keep their fans, in file order
    assert np.array_equal(sides, np.array([[p[0], p[j], p[j + 1]] for p in polygons[2:]
                                           for j in (1, 2)]))  # fmt: skip


def test_texture_coordinates_follow_the_corners_of_a_concave_face(tmp_path: Path):
    """Each triangle's texture corners are those of its position corners."""
    lines = [f"v {x} {y} 0" for x, y in U_SHAPE] + [f"vt {x / 3} {y / 2}" for x, y in U_SHAPE]
    lines.append("f " + " ".join(f"{i + 1}/{(i + 3) % 8 + 1}" for i in range(8)))
    (tmp_path / "u.obj").write_text("\n".join(lines))
    mesh = load_mesh(tmp_path / "u.obj")
    assert area(mesh.vertices, mesh.faces) == 5.0
    assert np.array_equal(mesh.uv_faces, (mesh.faces + 3) % 8)


def random_quads(count: int, seed: int) -> np.ndarray:
    """(count, 4, 3) quads seen from +z counter-clockwise, then turned at random: a third
    convex and planar, a third concave at a random corner (a dart), a third convex bent out of
    their plane."""
    rng = np.random.default_rng(seed)
    angles = rng.uniform(0, 2 * np.pi, (count, 1)) + np.pi / 2 * np.arange(4)
    angles += rng.uniform(-0.6, 0.6, (count, 4))  # a quarter turn apart, give or take
    radii = rng.uniform(0.5, 1.5, (count, 1)) * np.ones(4)  # on a circle: convex
    quads = np.stack([radii * np.cos(angles), radii * np.sin(angles), 0 * radii], axis=2)
    dart = np.arange(count) % 3 == 1
    notch = rng.integers(0, 4, count)
    rows = np.flatnonzero(dart)
    # A dart: one corner pulled past the diagonal of its two neighbours, inside the quad.
    before, after = quads[rows, (notch[rows] - 1) % 4], quads[rows, (notch[rows] + 1) % 4]
    opposite = quads[rows, (notch[rows] + 2) % 4]
    quads[rows, notch[rows]] = 0.7 * 0.5 * (before + after) + 0.3 * opposite
    bent = np.arange(count) % 3 == 2
    quads[bent, :, 2] = rng.uniform(-0.3, 0.3, (int(bent.sum()), 4))
    return quads @ rotation(seed).T


@pytest.mark.parametrize("seed", range(3))
def test_each_quad_takes_a_diagonal_inside_it(seed):
    quads = random_quads(600, seed)
    points = quads.reshape(-1, 3)
    corners = np.arange(len(points))
    triangles = triangulate(points, corners, np.full(len(quads), 4))
    assert triangles.shape == (2 * len(quads), 3)
    # Seen along the quad's own normal, both triangles turn the quad's way: none folds over.
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    p = points[triangles]
    sides = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                      np.repeat(normals, 2, axis=0))  # fmt: skip
    assert (sides > 0).all()
    # Each quad's two triangles use its four corners; convex ones keep the file's fan (0-2).
    assert (np.sort(triangles.reshape(-1, 6), axis=1) // 4 == np.arange(len(quads))[:, None]).all()
    planar_convex = np.arange(len(quads)) % 3 == 0
    fans = fan_of([4] * len(quads)).reshape(-1, 2, 3)
    assert np.array_equal(triangles.reshape(-1, 2, 3)[planar_convex], fans[planar_convex])


def test_quads_never_take_the_ear_clipping_path(monkeypatch):
    """Four corners have two triangulations, chosen for all quads at once: ear clipping (a
    Python loop, ~0.3 ms a polygon) is for polygons of five corners or more. Twisted quads
    (a bow tie seen along their normal) take the diagonal that folds least."""
    from gogreen_core.mesh.mesh_io import polygons

    def refuse(*args, **kwargs):
        raise AssertionError("ear clipping called for a quad")

    monkeypatch.setattr(polygons.mapbox_earcut, "triangulate_float64", refuse)
    rng = np.random.default_rng(7)
    quads = rng.normal(size=(3000, 4, 3))  # random: convex, concave, non-planar, twisted
    bow_tie = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0.0]])
    points = np.concatenate([quads.reshape(-1, 3), bow_tie])
    sizes = np.full(len(points) // 4, 4)
    triangles = triangulate(points, np.arange(len(points)), sizes)
    assert len(triangles) == 2 * len(sizes)
    assert (np.sort(triangles.reshape(-1, 6), axis=1) // 4 == np.arange(len(sizes))[:, None]).all()
    # Every corner is used by one of its quad's triangles (neighbours stay connected).
    assert len(np.unique(triangles)) == len(points)
