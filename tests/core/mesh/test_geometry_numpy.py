"""geometry.py's NumPy twins (``_geometry_numpy``) against its compiled functions: the same
index, the same faces picked, normals, boxes and hit points within 1e-12 relative, so that the
window picks and shades at once on a new machine and hands over to the compiled code without a
visible change."""

from __future__ import annotations

import numpy as np
import pytest

from gogreen_core._compiled import forced
from gogreen_core.mesh.geometry import SurfaceIndex
from gogreen_core.mesh.shapes import default_model, icosphere

STATE = ("order", "rank", "positions", "normals", "faces", "face_order", "_starts", "_ends",
         "_leaf_ids", "_face_normals", "_boxes",
         "_leaf_dirty")  # fmt: skip


def meshes():
    sphere, sphere_faces = icosphere(4)
    model, model_faces = default_model(4)
    # a vertex in no face (its normal is (0, 0, 1)) and a degenerate face
    loose = np.vstack([sphere, [[5.0, 5.0, 5.0]]])
    loose_faces = np.vstack([sphere_faces, [[0, 0, 1]]])
    return {"sphere": (sphere, sphere_faces), "model": (model, model_faces),
            "loose": (loose, loose_faces)}  # fmt: skip


def lifecycle(vertices, faces):
    """Build, two events, an undo found by comparison, picks: everything observable."""
    rng = np.random.default_rng(7)
    index = SurfaceIndex(vertices, faces)
    seen = [np.array(getattr(index, name)) for name in STATE]
    moved = vertices.copy()
    for count in (5, len(vertices) // 3):
        rows = np.sort(rng.choice(len(vertices), count, replace=False))
        moved[rows] += 0.05 * rng.normal(size=(count, 3))
        seen.append(np.array([index.update(moved, rows)]))
        seen += [np.array(getattr(index, name)) for name in STATE]
    changed = index.changed_rows(vertices)
    index.update(vertices, changed)
    seen.append(changed)
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    for _ in range(40):
        target = low + rng.random(3) * (high - low)
        origin = target + rng.normal(size=3) * 3.0
        hit = index.pick(origin, target - origin)
        seen.append(np.array([-1.0] if hit is None else [hit[0], *hit[1]]))
    seen.append(np.array(index._boxes))
    return seen


@pytest.mark.parametrize("name", ["sphere", "model", "loose"])
def test_numpy_twins_build_update_and_pick_alike(name):
    vertices, faces = meshes()[name]
    runs = {}
    for code in ("numpy", "unrolled"):
        with forced(code):
            runs[code] = lifecycle(vertices, faces)
    assert len(runs["numpy"]) == len(runs["unrolled"])
    for a, b in zip(runs["numpy"], runs["unrolled"], strict=True):
        assert a.dtype == b.dtype and a.shape == b.shape
        if a.dtype.kind == "f":  # float32 face normals: within their own rounding
            size = max(float(np.abs(a).max(initial=0.0)), 1.0)
            relative = 1e-6 if a.dtype == np.float32 else 1e-12
            assert np.abs(a - b).max(initial=0.0) <= relative * size
        else:
            assert np.array_equal(a, b)


def test_an_index_built_in_numpy_serves_the_compiled_code():
    vertices, faces = meshes()["model"]
    with forced("numpy"):
        index = SurfaceIndex(vertices, faces)
    reference = SurfaceIndex(vertices, faces)
    moved = vertices.copy()
    moved[:500] += 0.01
    with forced("unrolled"):
        index.update(moved, np.arange(500))
        reference.update(moved, np.arange(500))
    assert np.abs(index.normals - reference.normals).max() <= 1e-12
