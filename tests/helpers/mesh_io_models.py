"""Models and file layouts for the mesh file tests, written here independently of ``mesh_io``
(imported as ``from mesh_io_models import ...``; pytest puts ``tests/`` on the path).

The layouts are those Blender's exporters write by default (read from Blender's sources): OBJ
with ``o``, ``s``, ``usemtl`` lines, six-decimal positions, ``vn`` and ``vt`` records and
n-gons kept; binary little-endian PLY with float ``x y z s t`` and one vertex per distinct
(vertex, UV) pair in corner order (vertices split along UV seams), faces as
``list uchar uint``; binary STL of float32 triangles.
"""

from __future__ import annotations

import struct

import numpy as np

# A U: a 3 x 2 rectangle with a 1 x 1 notch, area 5; the fan from its first corner covers the
# notch (area 8).
U_SHAPE = [(0, 0), (3, 0), (3, 2), (2, 2), (2, 1), (1, 1), (1, 2), (0, 2)]
U_PRISM_AREA = 2 * 5 + (3 + 2 + 1 + 1 + 1 + 1 + 1 + 2)  # two caps, the sides (height 1)


class Model:
    """A polygon mesh: vertices (N, 3), polygons (lists of vertex numbers), per polygon the
    texture coordinate of each corner (or None), and a triangulation of it made by hand."""

    def __init__(self, vertices, polygons, corner_uv=None, triangles=None):
        self.vertices = np.asarray(vertices, dtype=np.float64)
        self.polygons = [list(p) for p in polygons]
        self.corner_uv = corner_uv
        self.triangles = None if triangles is None else np.asarray(triangles, dtype=np.int64)

    def area(self) -> float:
        return triangle_area(self.vertices, self.triangles)


def u_prism() -> Model:
    """The U extruded by 1: two concave 8-gon caps and 8 side quads, closed, area 22. Its UV
    map has seams around the caps and down one side edge."""
    bottom = [(x, y, 0) for x, y in U_SHAPE]
    top = [(x, y, 1) for x, y in U_SHAPE]
    polygons = [list(range(7, -1, -1)), list(range(8, 16))]  # outward: bottom reversed
    polygons += [[i, (i + 1) % 8, 8 + (i + 1) % 8, 8 + i] for i in range(8)]
    cap = [[0, 1, 4], [1, 2, 3], [1, 3, 4], [0, 4, 5], [0, 5, 7], [5, 6, 7]]  # the U by hand
    triangles = [[t[0], t[2], t[1]] for t in cap] + [[8 + a for a in t] for t in cap]
    triangles += [[p[0], p[1], p[2]] for p in polygons[2:]] + [[p[0], p[2], p[3]] for p in
                                                               polygons[2:]]  # fmt: skip
    perimeter = np.concatenate([[0], np.cumsum([3, 2, 1, 1, 1, 1, 1, 2])]) / 12
    corner_uv = [[(0.25 + x / 8, 0.25 + y / 8) for x, y in (U_SHAPE[i] for i in polygons[0])],
                 [(0.75 + x / 8, 0.25 + y / 8) for x, y in U_SHAPE]]  # fmt: skip
    corner_uv += [
        [(perimeter[i], 0.5), (perimeter[i + 1], 0.5), (perimeter[i + 1], 0.7), (perimeter[i], 0.7)]
        for i in range(8)
    ]
    return Model(bottom + top, polygons, corner_uv, triangles)


def uv_sphere(rings: int = 12, segments: int = 16) -> Model:
    """A UV sphere as Blender makes one: triangle fans at the poles, quads between, its UV map
    cut along one meridian (the seam) and at the poles."""
    theta = np.pi * np.arange(1, rings) / rings
    phi = 2 * np.pi * np.arange(segments) / segments
    ring = np.stack(
        [
            np.outer(np.sin(theta), np.cos(phi)),
            np.outer(np.sin(theta), np.sin(phi)),
            np.outer(np.cos(theta), np.ones(segments)),
        ],
        axis=2,
    ).reshape(-1, 3)
    vertices = np.round(np.concatenate([[[0, 0, 1.0]], ring, [[0, 0, -1.0]]]), 6)
    south = len(vertices) - 1

    def at(r: int, s: int) -> int:  # ring 1..rings-1, segment (wraps)
        return 1 + (r - 1) * segments + s % segments

    def uv(r: float, s: float) -> tuple[float, float]:
        return (s / segments, 1 - r / rings)

    polygons, corner_uv = [], []
    for s in range(segments):
        polygons.append([0, at(1, s), at(1, s + 1)])
        corner_uv.append([uv(0, s + 0.5), uv(1, s), uv(1, s + 1)])
    for r in range(1, rings - 1):
        for s in range(segments):
            polygons.append([at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)])
            corner_uv.append([uv(r, s), uv(r + 1, s), uv(r + 1, s + 1), uv(r, s + 1)])
    for s in range(segments):
        polygons.append([at(rings - 1, s + 1), at(rings - 1, s), south])
        corner_uv.append([uv(rings - 1, s + 1), uv(rings - 1, s), uv(rings, s + 0.5)])
    triangles = [[p[0], p[j], p[j + 1]] for p in polygons for j in range(1, len(p) - 1)]
    return Model(vertices, polygons, corner_uv, triangles)


def triangle_area(vertices: np.ndarray, triangles: np.ndarray) -> float:
    t = np.asarray(vertices, dtype=np.float64)[triangles]
    return 0.5 * float(np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum())


def edges_used_once(faces: np.ndarray) -> int:
    """Boundary edges (0 for a closed surface)."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


# -- Blender's layouts -------------------------------------------------------------------------
def blender_obj(objects: dict[str, Model], smooth: str = "s 0") -> str:
    """OBJ as Blender 4 writes it by default: UVs, normals, materials, n-gons kept."""
    lines = ["# Blender 4.2.0", "# www.blender.org", "mtllib scene.mtl"]
    v_base = vt_base = vn_base = 0
    for name, model in objects.items():
        lines.append(f"o {name}")
        lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in model.vertices.tolist()]
        normals = []
        for p in model.polygons:
            pts = model.vertices[p]
            n = np.cross(pts[1] - pts[0], pts[2] - pts[0])
            normals.append(n / np.linalg.norm(n))
        lines += [f"vn {x:.4f} {y:.4f} {z:.4f}" for x, y, z in normals]
        uvs = [uv for corners in model.corner_uv for uv in corners]
        lines += [f"vt {u:.6f} {v:.6f}" for u, v in uvs]
        lines += [smooth, "usemtl Material"]
        corner = 0
        for k, polygon in enumerate(model.polygons):
            items = []
            for i in polygon:
                items.append(f"{v_base + i + 1}/{vt_base + corner + 1}/{vn_base + k + 1}")
                corner += 1
            lines.append("f " + " ".join(items))
        v_base += len(model.vertices)
        vt_base += len(uvs)
        vn_base += len(normals)
    return "\n".join(lines) + "\n"


def blender_ply_split(model: Model) -> tuple[np.ndarray, np.ndarray, list[list[int]]]:
    """Blender's PLY vertex map with UVs: one PLY vertex per distinct (vertex, UV) pair in
    corner order, then the loose vertices with UV (0, 0). Returns positions (V, 3), uv (V, 2)
    and the polygons on the PLY vertices."""
    keys: dict[tuple[int, float, float], int] = {}
    polygons = []
    for polygon, uvs in zip(model.polygons, model.corner_uv, strict=True):
        pairs = zip(polygon, uvs, strict=True)
        polygons.append([keys.setdefault((v, *uv), len(keys)) for v, uv in pairs])
    used = {v for v, _, _ in keys}
    for v in range(len(model.vertices)):
        if v not in used:
            keys[(v, 0.0, 0.0)] = len(keys)
    table = np.array(list(keys), dtype=np.float64)
    source = table[:, 0].astype(int)
    return model.vertices[source], table[:, 1:], polygons


def blender_ply(model: Model, ascii: bool = False, export_uv: bool = True) -> bytes:
    """PLY as Blender 4 writes it by default (binary, with UVs, n-gons kept); without UVs
    (``export_uv`` off) the vertices are Blender's, in its order."""
    if export_uv:
        positions, uv, polygons = blender_ply_split(model)
        table = np.concatenate([positions, uv], axis=1).astype("<f4")
    else:
        table, polygons = model.vertices.astype("<f4"), model.polygons
    header = (
        "ply\n"
        f"format {'ascii' if ascii else 'binary_little_endian'} 1.0\n"
        "comment Created in Blender version 4.2.0\n"
        f"element vertex {len(table)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        + ("property float s\nproperty float t\n" if export_uv else "")
        + f"element face {len(polygons)}\n"
        "property list uchar uint vertex_indices\nend_header\n"
    ).encode()
    if ascii:
        rows = "".join(" ".join(repr(float(x)) for x in row) + "\n" for row in table)
        faces = "".join(f"{len(p)} " + " ".join(map(str, p)) + "\n" for p in polygons)
        return header + (rows + faces).encode()
    faces_bytes = b"".join(struct.pack(f"<B{len(p)}I", len(p), *p) for p in polygons)
    return header + table.tobytes() + faces_bytes


def binary_stl(vertices: np.ndarray, triangles: np.ndarray) -> bytes:
    """Binary STL as Blender writes it: float32 normal and corners, attribute 0."""
    corners = np.asarray(vertices, dtype=np.float64)[triangles].astype("<f4")
    records = b""
    for tri in corners:
        n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        n = (n / np.linalg.norm(n)).astype("<f4")
        records += n.tobytes() + tri.tobytes() + b"\0\0"
    return (
        b"Exported from Blender-4.2.0".ljust(80, b"\0") + struct.pack("<I", len(corners)) + records
    )
