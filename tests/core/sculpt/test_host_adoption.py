"""What a host application (the Blender extension) hands the engine between strokes: positions
changed by its own tools or undo (:meth:`Sculptor.adopt_vertices`) and its sculpt mask
(:meth:`Mask.adopt`)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, ParameterError, Sculptor
from gogreen_core.mesh.shapes import icosphere


@pytest.fixture
def sculptor() -> Sculptor:
    vertices, faces = icosphere(2)
    return Sculptor(vertices, faces, l_max=2)


def _grab(sculptor: Sculptor) -> np.ndarray:
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    event = BrushEvent(center=top, delta=np.array([0.0, 0.0, 0.1]))
    return sculptor.apply_brush(Brush("grab", radius=0.2), [event])


def test_adopted_vertices_are_what_the_next_stroke_starts_from():
    vertices, faces = icosphere(2)
    vertices = vertices.astype(np.float32).astype(np.float64)  # as a host keeps them
    sculptor = Sculptor(vertices, faces, l_max=2)
    _grab(sculptor)
    assert sculptor.history.can_undo
    host = vertices.copy()  # the host undid the stroke, then one of its brushes moved a
    inner = np.flatnonzero(np.abs(vertices).max(axis=1) < 0.8)[:40]
    host[inner] *= 0.9  # patch inwards (the bounding box, so the model size, stays)
    rows = sculptor.adopt_vertices(host)
    assert np.array_equal(sculptor.vertices, host) and set(inner) <= set(rows)
    assert not sculptor.history.can_undo  # its steps would undo to positions gone
    assert len(sculptor.adopt_vertices(host)) == 0  # nothing changed: nothing written
    # the next stroke is the one a new sculptor on the host's positions makes (the mesh's
    # search blocks were told of the written rows)
    fresh = Sculptor(host, faces, l_max=2)
    assert fresh.model_size == sculptor.model_size
    _grab(sculptor)
    _grab(fresh)
    assert np.array_equal(sculptor.vertices, fresh.vertices)


def test_adopting_vertices_is_refused_when_wrong(sculptor):
    with pytest.raises(ParameterError, match="shape"):
        sculptor.adopt_vertices(np.zeros((3, 3)))
    bad = sculptor.vertices.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ParameterError, match="finite"):
        sculptor.adopt_vertices(bad)
    sculptor.begin_stroke(Brush("grab"))
    with pytest.raises(RuntimeError, match="during a stroke"):
        sculptor.adopt_vertices(sculptor.vertices.copy())


def test_an_adopted_mask_holds_and_scales_the_motion(sculptor):
    vertices = sculptor.vertices.copy()
    held = np.where(vertices[:, 0] > 0.0, 1.0, 0.0)
    held[np.flatnonzero(vertices[:, 0] <= 0.0)[:5]] = 0.5
    rows = sculptor.mask.adopt(held)
    assert np.array_equal(sculptor.mask.values, held) and len(rows) == np.count_nonzero(held)
    free = Sculptor(vertices, sculptor.faces, l_max=2)
    _grab(sculptor)
    _grab(free)
    moved = sculptor.vertices - vertices
    assert not np.any(moved[held == 1.0])  # the masked half stays put
    half = held == 0.5
    np.testing.assert_allclose(moved[half], 0.5 * (free.vertices - vertices)[half], atol=1e-12)
    with pytest.raises(ParameterError, match=r"\[0, 1\]"):
        sculptor.mask.adopt(np.full(len(vertices), 1.5))
    with pytest.raises(ParameterError, match="shape"):
        sculptor.mask.adopt(np.zeros(4))


def test_the_compiling_child_imports_what_this_process_does(monkeypatch, tmp_path):
    """An application embedding Python (Blender) puts its extensions' wheels on sys.path at run
    time: the child that compiles the kernels gets the same path."""
    import subprocess
    import sys

    from gogreen_core import _compiled

    seen = {}

    class Child:  # the compiling child, as far as _compile_in_child reads it
        def __init__(self, args, env, **_kwargs):
            seen.update(env)
            self.stdout = iter(())

        def wait(self):
            return 0

        def kill(self):
            pass

    wheels = str(tmp_path / "extensions" / "site-packages")
    monkeypatch.setattr(sys, "path", [*sys.path, wheels])
    monkeypatch.setattr(subprocess, "Popen", Child)
    assert _compiled._compile_in_child([_compiled.GEOMETRY])
    assert wheels in seen["PYTHONPATH"].split(os.pathsep)
