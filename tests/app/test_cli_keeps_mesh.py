"""Every command of the command line that writes a mesh keeps what ``load_mesh`` read besides
the positions: the faces and the texture coordinates of each face corner (issue 37, item 1).

Each command runs on Spot's stand-in made here (UV seams: more texture coordinates than
vertices) and on Spot itself (3,225 ``vt``; skipped when ../shared is absent), writing OBJ and
PLY."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.files.journal import Journal
from gogreen_core.interaction.batch import main
from gogreen_core.mesh.mesh_io import MeshData, load_mesh


@pytest.fixture(params=["made", "spot.obj"])
def textured(request, made_textured, shared_mesh) -> Path:
    """A mesh with per-corner texture coordinates: the made one or Spot."""
    return made_textured.path if request.param == "made" else shared_mesh(request.param)


def corner_uv(mesh: MeshData) -> np.ndarray:
    """(M, 3, 2) the texture coordinates of each face corner (what a renderer sees)."""
    assert mesh.uv is not None and mesh.uv_faces is not None, "texture coordinates dropped"
    return mesh.uv[mesh.uv_faces]


def assert_same_surface_data(written: Path, read: MeshData) -> None:
    out = load_mesh(written)
    assert np.array_equal(out.faces, read.faces)
    assert np.array_equal(corner_uv(out), corner_uv(read))


def grab_arguments(mesh: MeshData) -> list[str]:
    center = mesh.vertices[len(mesh.vertices) // 3]
    return ["--center", *map(repr, center.tolist()), "--delta", "0", "0.05", "0.02", "-q"]


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_deform_keeps_the_texture_coordinates(tmp_path, textured, suffix):
    read = load_mesh(textured)
    out = tmp_path / f"out{suffix}"
    assert main(["deform", str(textured), "-o", str(out), *grab_arguments(read)]) == 0
    assert_same_surface_data(out, read)
    assert not np.array_equal(load_mesh(out).vertices, read.vertices)  # it did deform


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_replay_keeps_the_texture_coordinates_and_equals_deform(tmp_path, textured, suffix):
    read = load_mesh(textured)
    deformed, session = tmp_path / f"deformed{suffix}", tmp_path / "session.json"
    argv = ["deform", str(textured), "-o", str(deformed), "--session-out", str(session)]
    assert main(argv + grab_arguments(read)) == 0
    replayed = tmp_path / f"replayed{suffix}"
    assert main(["replay", str(session), str(textured), "-o", str(replayed), "-q"]) == 0
    assert_same_surface_data(replayed, read)
    # The two outputs are the same file: same positions, faces and texture coordinates.
    assert replayed.read_bytes() == deformed.read_bytes()


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
def test_recover_keeps_the_texture_coordinates(tmp_path, textured, suffix):
    read = load_mesh(textured)
    sculptor = Sculptor(read.vertices, read.faces, uv=read.uv, uv_faces=read.uv_faces)
    journal = Journal(sculptor, read, document=str(textured))  # the default place (conftest)
    center = read.vertices[len(read.vertices) // 3].copy()
    sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(center, np.array([0, 0.05, 0]))])
    journal.flush()
    directory = journal.directory
    journal.close(remove=False)  # as a crash leaves it
    out = tmp_path / f"recovered{suffix}"
    assert main(["recover", directory.name, "-o", str(out), "-q"]) == 0
    assert_same_surface_data(out, read)
    assert np.array_equal(load_mesh(out).vertices, sculptor.vertices)
