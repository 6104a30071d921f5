"""Benchmark of mesh file loading (issue "Mesh files as Blender and others write them").

    python benchmarks/mesh_io.py [--repeats 7] [--cold-compile]

Writes its files into a temporary folder (nothing downloaded) and prints medians of
``load_mesh`` for:

* binary PLY, 200,000 faces: all triangles, against triangles and quads mixed at random (the
  worst case for a reader that walks records: every other record changes size) and in runs
  (Blender's order: quads with triangle fans at the poles), and half triangles, half quads of
  four random vertices each (convex, concave, non-planar and twisted: each quad's diagonal is
  chosen by its shape, all quads at once); the same in ASCII;
* binary PLY as Blender writes it by default (float positions, ``s, t`` with vertices split at
  UV seams, quads and n-gons) of a UV sphere, welded back at load;
* binary STL of 520,000 triangles (26 MB), against ``trimesh.load`` on the same file (with
  ``process=False``, which keeps 3 corners per triangle, and with its default processing, which
  merges vertices like ``load_mesh`` does);
* OBJ of 1M vertices with quads (all convex: triangulated by fans as before) and with concave
  n-gons (ear clipping), to show what triangulating by shape costs.

``--cold-compile`` also times ``mesh_io.warm_up()`` in a fresh process with an empty numba cache
(compiling the PLY record walks, the fan test and the welds, once per machine). Figures only, no
assertions.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import trimesh

from gogreen_core.mesh.mesh_io import load_mesh

FACES = 200_000


def median_ms(samples: list[float]) -> str:
    return f"{1e3 * statistics.median(samples):8.1f} ms (min {1e3 * min(samples):.1f})"


def timed(load: Callable[[], object], repeats: int) -> list[float]:
    load()  # warm: file cache, compiled code
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        load()
        samples.append(time.perf_counter() - start)
    return samples


def torus_quads(n_quads: int) -> tuple[np.ndarray, np.ndarray]:
    """A torus grid of about ``n_quads`` quads: vertices (N, 3) float64, quads (Q, 4), row by
    row of an even number of quads."""
    rings = 2 * int(np.sqrt(n_quads / 8))
    segments = n_quads // rings
    u, v = np.meshgrid(
        2 * np.pi * np.arange(rings) / rings, 2 * np.pi * np.arange(segments) / segments
    )
    u, v = u.ravel(), v.ravel()
    vertices = np.stack(
        [(2 + np.cos(v)) * np.cos(u), (2 + np.cos(v)) * np.sin(u), np.sin(v)], axis=1
    )
    i, j = np.meshgrid(np.arange(rings), np.arange(segments))
    i, j = i.ravel(), j.ravel()

    def at(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return (b % segments) * rings + a % rings

    quads = np.stack([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)], axis=1)
    return vertices, quads


def mixed_faces(quads: np.ndarray, split: np.ndarray) -> list[np.ndarray]:
    """Each quad, or its two triangles where ``split`` is set, in quad order."""
    faces: list[np.ndarray] = []
    for quad, cut in zip(quads, split, strict=True):
        if cut:
            faces += [quad[[0, 1, 2]], quad[[0, 2, 3]]]
        else:
            faces.append(quad)
    return faces


def random_quads(
    vertices: np.ndarray, triangles: list[np.ndarray], rng: np.random.Generator
) -> list[np.ndarray]:
    """As many faces as ``triangles``: its first half, then quads of four distinct random
    vertices (most of them non-planar; seen along their normal convex, concave or twisted)."""
    half = len(triangles) // 2
    quads = rng.integers(0, len(vertices), (len(triangles) - half, 4))
    while (repeated := (np.diff(np.sort(quads, axis=1), axis=1) == 0).any(axis=1)).any():
        quads[repeated] = rng.integers(0, len(vertices), (int(repeated.sum()), 4))
    return triangles[:half] + list(quads)


def ply_bytes(
    vertices: np.ndarray,
    faces: list[np.ndarray],
    ascii: bool = False,
    uv: np.ndarray | None = None,
) -> bytes:
    """PLY as Blender writes it: float x y z (and s t), faces as ``list uchar uint``."""
    header = (
        "ply\n"
        f"format {'ascii' if ascii else 'binary_little_endian'} 1.0\n"
        "comment Created in Blender version 4.2.0\n"
        f"element vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        + ("property float s\nproperty float t\n" if uv is not None else "")
        + f"element face {len(faces)}\n"
        "property list uchar uint vertex_indices\nend_header\n"
    )
    table = vertices if uv is None else np.concatenate([vertices, uv], axis=1)
    if ascii:
        rows = "\n".join(" ".join(f"{x:g}" for x in row) for row in table.astype(np.float32))
        polygons = "\n".join(f"{len(f)} " + " ".join(map(str, f)) for f in faces)
        return (header + rows + "\n" + polygons + "\n").encode()
    records = [np.array([len(f)], "u1").tobytes() + np.asarray(f, "<u4").tobytes() for f in faces]
    return header.encode() + table.astype("<f4").tobytes() + b"".join(records)


def stl_bytes(vertices: np.ndarray, triangles: np.ndarray) -> bytes:
    record = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    data = np.zeros(len(triangles), dtype=record)
    data["v"] = vertices[triangles]
    return b"\0" * 80 + np.uint32(len(triangles)).tobytes() + data.tobytes()


def obj_bytes(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    rows = "".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in vertices.tolist())
    polys = "".join("f " + " ".join(str(i + 1) for i in f) + "\n" for f in faces.tolist())
    return (rows + polys).encode()


def uv_sphere_blender_ply(rings: int = 400, segments: int = 800) -> bytes:
    """A UV sphere exported the way Blender's PLY exporter does by default: one PLY vertex per
    distinct (vertex, UV) pair in corner order, so the seam meridian and the poles are split."""
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
    points = np.concatenate([[[0, 0, 1.0]], ring, [[0, 0, -1.0]]])
    south = len(points) - 1

    def vid(r: int, s: int) -> int:
        return 1 + (r - 1) * segments + s % segments

    faces, corner_uv = [], []
    for s in range(segments):  # north fan, quads, south fan
        faces.append([0, vid(1, s), vid(1, s + 1)])
        corner_uv.append([((s + 0.5) / segments, 1.0), (s / segments, 1 - 1 / rings),
                          ((s + 1) / segments, 1 - 1 / rings)])  # fmt: skip
    for r in range(1, rings - 1):
        for s in range(segments):
            faces.append([vid(r, s), vid(r + 1, s), vid(r + 1, s + 1), vid(r, s + 1)])
            u0, u1 = s / segments, (s + 1) / segments
            v0, v1 = 1 - r / rings, 1 - (r + 1) / rings
            corner_uv.append([(u0, v0), (u0, v1), (u1, v1), (u1, v0)])
    for s in range(segments):
        faces.append([vid(rings - 1, s + 1), vid(rings - 1, s), south])
        corner_uv.append([((s + 1) / segments, 1 / rings), (s / segments, 1 / rings),
                          ((s + 0.5) / segments, 0.0)])  # fmt: skip
    keys: dict[tuple[int, float, float], int] = {}
    split_faces = []
    for face, uvs in zip(faces, corner_uv, strict=True):
        split_faces.append(
            np.array(
                [keys.setdefault((v, *uv), len(keys)) for v, uv in zip(face, uvs, strict=True)]
            )
        )
    table = np.array([(*points[v], u, w) for v, u, w in keys], dtype=np.float64)
    return ply_bytes(table[:, :3], split_faces, uv=table[:, 3:])


def cold_warm_up() -> float:
    """Seconds of ``mesh_io.warm_up()`` (compiling every loop the readers run) in a fresh
    process whose numba cache directory is empty: the first file opened on a new machine."""
    code = "from gogreen_core.mesh.mesh_io import warm_up\nprint(warm_up())\n"
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        result = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        )
    return float(result.stdout.split()[-1])


def interleaved(loads: dict[str, Callable[[], object]], repeats: int) -> dict[str, list[float]]:
    """Seconds of each load, taken in turn in every round so that the machine's noise hits all
    alike (the first round warms the file cache and the compiled code and is dropped)."""
    samples: dict[str, list[float]] = {label: [] for label in loads}
    for round_ in range(repeats + 1):
        for label, load in loads.items():
            start = time.perf_counter()
            load()
            if round_:
                samples[label].append(time.perf_counter() - start)
    return samples


def report(samples: dict[str, list[float]], notes: dict[str, str], reference: str) -> None:
    base = statistics.median(samples[reference])
    for label, values in samples.items():
        ratio = statistics.median(values) / base
        print(f"  {label:30s} {median_ms(values)}  {ratio:5.2f}x   {notes.get(label, '')}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--cold-compile", action="store_true")
    parser.add_argument("--ply-only", action="store_true", help="only the PLY tables")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        vertices, quads = torus_quads(FACES // 2)
        all_tri = mixed_faces(quads, np.ones(len(quads), bool))
        vertices_m, quads_m = torus_quads(FACES * 2 // 3)
        n_split = FACES - len(quads_m)
        shuffled = np.zeros(len(quads_m), bool)
        shuffled[rng.choice(len(quads_m), n_split, replace=False)] = True
        runs = np.zeros(len(quads_m), bool)
        runs[:n_split] = True
        meshes = {
            "all triangles": (vertices, all_tri),
            "tri/quad mixed at random": (vertices_m, mixed_faces(quads_m, shuffled)),
            "tri/quad mixed in runs": (vertices_m, mixed_faces(quads_m, runs)),
            "half random quads": (vertices, random_quads(vertices, all_tri, rng)),
        }
        for kind in ("binary", "ASCII"):
            loads, notes = {}, {}
            for number, (label, (points, faces)) in enumerate(meshes.items()):
                path = tmp / f"{kind}{number}.ply"
                path.write_bytes(ply_bytes(points, faces, ascii=kind == "ASCII"))
                loads[label] = lambda p=path: load_mesh(p)
                triangles = len(load_mesh(path).faces)
                notes[label] = f"{path.stat().st_size / 1e6:5.1f} MB, {triangles} triangles"
            print(f"{kind} PLY, {FACES:,} faces (medians of {args.repeats}, ratio to the first):")
            report(interleaved(loads, args.repeats), notes, "all triangles")
        if args.cold_compile:
            print(f"warm_up() from an empty numba cache: {cold_warm_up():.2f} s")
        if args.ply_only:
            return

        sphere = tmp / "blender_uv_sphere.ply"
        sphere.write_bytes(uv_sphere_blender_ply())
        mesh = load_mesh(sphere)
        figure = median_ms(timed(lambda: load_mesh(sphere), args.repeats))
        print(
            f"Blender-layout PLY UV sphere ({sphere.stat().st_size / 1e6:.1f} MB): {figure}   "
            f"{len(mesh.vertices)} vertices after loading, {edges_open(mesh.faces)} open edges"
        )

        v_stl, q_stl = torus_quads(260_000)
        triangles = np.concatenate([q_stl[:, [0, 1, 2]], q_stl[:, [0, 2, 3]]])
        stl = tmp / "torus.stl"
        stl.write_bytes(stl_bytes(v_stl, triangles))
        loads = {
            "load_mesh (welded)": lambda: load_mesh(stl),
            "trimesh.load process=False": lambda: trimesh.load(stl, process=False),
            "trimesh.load (merges)": lambda: trimesh.load(stl),
        }
        notes = {label: f"{len(load().vertices)} vertices" for label, load in loads.items()}
        size = stl.stat().st_size / 1e6
        print(f"binary STL, {len(triangles):,} triangles ({size:.0f} MB), ratio to trimesh's:")
        report(interleaved(loads, args.repeats), notes, "trimesh.load process=False")

        v_obj, q_obj = torus_quads(1_000_000)
        quads_obj = tmp / "quads.obj"
        quads_obj.write_bytes(obj_bytes(v_obj, q_obj))
        # Hexagons (two quads side by side), each made concave by pulling its second corner
        # towards its middle (which pushes out the top middle corner of the one below).
        left, right = q_obj[0::2], q_obj[1::2]
        hexagons = np.concatenate([left[:, :2], right[:, 1:], left[:, 3:]], axis=1)
        pulled = v_obj.copy()
        pulled[left[:, 1]] += 0.6 * (v_obj[left[:, 2]] - v_obj[left[:, 1]])
        concave = tmp / "concave.obj"
        concave.write_bytes(obj_bytes(pulled, hexagons))
        print(f"OBJ, {len(v_obj):,} vertices (ratio to the quads):")
        loads = {
            "convex quads": lambda: load_mesh(quads_obj),
            "concave 6-gons": lambda: load_mesh(concave),
        }
        report(interleaved(loads, args.repeats), {}, "convex quads")


def edges_open(faces: np.ndarray) -> int:
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


if __name__ == "__main__":
    main()
