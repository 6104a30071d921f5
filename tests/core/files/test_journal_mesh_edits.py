"""Crash recovery of the mesh edits: the mask and a subdivision live in the journal's start,
its checkpoints and its records, and a recovery continues bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from test_journal import checkpoint, crash, journaled, stroke

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.files.journal import Journal
from gogreen_core.files.recovery import recover
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.checkpoint import read_checkpoint


@pytest.fixture
def mesh():
    import journal_script

    return journal_script.mesh()


def mask_top(sculptor: Sculptor) -> None:
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))]
    sculptor.apply_brush(Brush("mask", radius=0.1), [BrushEvent(top, amount=1.0)])


def same(a: Sculptor, b: Sculptor) -> bool:
    x, y = a.mesh, b.mesh
    return all(
        (p is None and q is None) or (p is not None and q is not None and np.array_equal(p, q))
        for p, q in zip(
            (x.vertices, x.faces, x.mask, x.uv, x.uv_faces),
            (y.vertices, y.faces, y.mask, y.uv, y.uv_faces),
            strict=True,
        )
    )


def test_a_checkpoint_holds_the_mask(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    mask_top(sculptor)
    checkpoint(journal)
    stroke(sculptor, 1)
    checkpoint(journal)
    directory = crash(journal)
    newest = max(directory.glob("checkpoint-*.bin"), key=lambda p: p.stat().st_mtime)
    state, _meta = read_checkpoint(newest)
    assert state.mask is not None and state.faces is None  # no new faces: none stored
    for budget in (0, np.inf):  # from the newest checkpoint, and from the start
        recovery = recover(directory, budget=budget)
        assert same(recovery.sculptor, sculptor), budget
        stroke(recovery.sculptor, 2)
        recovery.release()
    stroke(sculptor, 2)
    assert same(recovery.sculptor, sculptor)  # the mask held the same vertices


def test_a_subdivided_mesh_is_recovered_from_its_checkpoint(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    stroke(sculptor, 0)
    mask_top(sculptor)
    sculptor.subdivide(unmasked_only=True)
    stroke(sculptor, 1)
    checkpoint(journal)
    directory = crash(journal)
    recovery = recover(directory, budget=0)
    assert recovery.replayed == 0  # the checkpoint after the subdivision was used
    assert same(recovery.sculptor, sculptor)
    assert np.array_equal(recovery.mesh.faces, sculptor.faces)  # what `recover -o` writes
    assert len(recovery.mesh.vertices) == len(sculptor.vertices)
    recovery.release()
    recovery = recover(directory, budget=np.inf)  # from the start: the subdivision replayed
    assert recovery.replayed == 4 and same(recovery.sculptor, sculptor)
    recovery.sculptor.undo()
    recovery.sculptor.undo()
    sculptor.undo()
    sculptor.undo()
    assert same(recovery.sculptor, sculptor) and len(sculptor.faces) == len(mesh.faces)
    recovery.release()


def test_a_journal_restarted_after_a_subdivision_starts_from_the_finer_mesh(tmp_path):
    vertices, faces = icosphere(2)
    from gogreen_core.mesh.mesh_io import MeshData

    loaded = MeshData(vertices, faces, uv=vertices[:, :2].copy(), uv_faces=faces.copy())
    sculptor = Sculptor(vertices, faces, uv=loaded.uv, uv_faces=loaded.uv_faces)
    journal = Journal(sculptor, loaded, root=tmp_path, auto_checkpoint=False)
    mask_top(sculptor)
    sculptor.subdivide()
    journal.restart()  # a save: the journal starts from the subdivided, masked mesh
    stroke(sculptor, 3)
    directory = crash(journal)
    recovery = recover(directory, budget=np.inf)
    assert recovery.start == 0 and recovery.replayed == 1
    assert same(recovery.sculptor, sculptor)
    assert recovery.mesh.uv is not None and len(recovery.mesh.faces) == 4 * len(faces)
    recovery.release()


def test_dynamic_topology_strokes_and_a_remesh_are_recovered(mesh, tmp_path):
    sculptor, journal = journaled(mesh, tmp_path, auto_checkpoint=False)
    sculptor.change_settings(dynamic_topology=True, detail_size=0.015)
    stroke(sculptor, 0)
    assert len(sculptor.faces) != len(mesh.faces)  # the stroke remeshed
    checkpoint(journal)
    stroke(sculptor, 1)
    sculptor.remesher.remesh(0.04)
    directory = crash(journal)
    for budget in (0, np.inf):  # from the checkpoint, and from the start
        recovery = recover(directory, budget=budget)
        assert same(recovery.sculptor, sculptor), budget
        assert recovery.sculptor.settings == sculptor.settings
        recovery.release()


def test_a_textured_dynamic_topology_stroke_and_its_undo_are_recovered(tmp_path):
    """The undo step of a textured mesh's dynamic-topology stroke (what changed, texture rows
    included) is made again by the recovery's replay: redo and undo give the arrays back."""
    from gogreen_core.mesh.mesh_io import MeshData

    vertices, faces = icosphere(4)
    loaded = MeshData(vertices, faces, uv=vertices[:, :2].copy(), uv_faces=faces.copy())
    sculptor = Sculptor(vertices, faces, uv=loaded.uv, uv_faces=loaded.uv_faces)
    start = sculptor.mesh
    journal = Journal(sculptor, loaded, root=tmp_path, auto_checkpoint=False)
    sculptor.change_settings(dynamic_topology=True, detail_size=0.03)
    stroke(sculptor, 0)
    assert len(sculptor.faces) != len(faces)  # the stroke remeshed
    checkpoint(journal)
    stroke(sculptor, 1)
    stroked = Sculptor(vertices, faces)
    stroked._mesh.adopt(sculptor.mesh)
    sculptor.undo()
    directory = crash(journal)
    for budget in (0, np.inf):  # from the checkpoint, and from the start
        recovery = recover(directory, budget=budget)
        again = recovery.sculptor
        assert same(again, sculptor), budget
        again.redo()
        assert same(again, stroked) and again.mesh.uv is not None
        if budget:
            for _ in range(3):  # the strokes and the setting
                assert again.undo() is not None
            unchanged = Sculptor(vertices, faces)
            unchanged._mesh.adopt(start)
            assert same(again, unchanged)
        recovery.release()
