"""Shared test helpers: the shared meshes found relative to the checkout, and meshes the project
makes itself so that a clone without ``../shared`` still tests the same things.

The shared meshes (``../shared/meshes`` beside the checkout: Spot, the Stanford bunny, the Ogre)
each stand for a property: Spot has UV seams (``vt`` records, per-corner texture coordinates,
more texture coordinates than vertices), the bunny is open (holes) and tiny (~0.15 units), the
Ogre is huge (~30 units). The made meshes below have the same properties (checked in
``test_mesh_io.py``), and are written as OBJ text here, independently of ``mesh_io``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from gogreen_core.mesh.shapes import default_model, icosphere

#: ``shared/meshes`` in the checkout's parent directory (absent in a user's clone).
SHARED_MESHES = Path(__file__).resolve().parent.parent.parent / "shared" / "meshes"


def find_shared_mesh(name: str) -> Path:
    """Path of ``../shared/meshes/<name>`` beside the checkout; skips the test when absent."""
    path = SHARED_MESHES / name
    if not path.is_file():
        pytest.skip(
            f"shared mesh {name} not found in {SHARED_MESHES} (../shared/meshes beside the "
            "checkout); project-made meshes cover the same checks"
        )
    return path


@pytest.fixture(scope="session")
def shared_mesh() -> Callable[[str], Path]:
    """``shared_mesh("spot.obj")``: the shared mesh's path, or a skip with the reason."""
    return find_shared_mesh


@dataclass
class MadeMesh:
    """A project-made mesh written as OBJ text, with the arrays it was written from."""

    path: Path
    vertices: np.ndarray  # (N, 3) float64, exactly the file's decimal values
    faces: np.ndarray  # (M, 3) int64, fan-triangulated like load_mesh does
    uv: np.ndarray | None = None  # (T, 2) float64
    uv_faces: np.ndarray | None = None  # (M, 3) int64


def _bumpy(points: np.ndarray) -> np.ndarray:
    """Unit-sphere points pushed along their radii by smooth bumps (an organic shape)."""
    radius = 1.0 + 0.15 * np.sin(3 * points[:, 0]) * np.cos(2 * points[:, 1]) + 0.1 * points[:, 2]
    return points * radius[:, None]


def textured_seamed_mesh() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A bumpy latitude-longitude sphere (~2 units) with a UV seam, like Spot.

    Returns vertices (N, 3), quads and pole triangles as polygons (a list of position-index
    lists), their texture-index lists, and uv (T, 2): the seam meridian and the poles have
    several texture coordinates per vertex, so T > N.
    """
    rings, segments = 24, 36
    theta = np.pi * np.arange(1, rings) / rings  # interior rings
    phi = 2 * np.pi * np.arange(segments) / segments
    ring_points = np.stack(
        [
            np.outer(np.sin(theta), np.cos(phi)),
            np.outer(np.sin(theta), np.sin(phi)),
            np.outer(np.cos(theta), np.ones(segments)),
        ],
        axis=2,
    ).reshape(-1, 3)
    points = np.concatenate([[[0.0, 0.0, 1.0]], ring_points, [[0.0, 0.0, -1.0]]])
    vertices = np.round(_bumpy(points) * [1.2, 0.8, 0.9], 6)  # decimal values, like most files
    south = len(vertices) - 1

    def ring_vertex(i: int, j: int) -> int:  # ring i in 0..rings-2, segment j (wraps)
        return 1 + i * segments + j % segments

    # Texture coordinates: (segments + 1) per interior ring (the seam column twice), and one
    # per segment at each pole.
    u = np.arange(segments + 1) / segments
    uv_rings = np.stack(
        [np.tile(u, rings - 1), np.repeat(1 - np.arange(1, rings) / rings, segments + 1)], axis=1
    )
    uv_north = np.stack([(np.arange(segments) + 0.5) / segments, np.ones(segments)], axis=1)
    uv_south = np.stack([(np.arange(segments) + 0.5) / segments, np.zeros(segments)], axis=1)
    uv = np.round(np.concatenate([uv_north, uv_rings, uv_south]), 6)

    def ring_uv(i: int, j: int) -> int:
        return segments + i * (segments + 1) + j

    polygons, textures = [], []
    for j in range(segments):
        polygons.append([0, ring_vertex(0, j), ring_vertex(0, j + 1)])
        textures.append([j, ring_uv(0, j), ring_uv(0, j + 1)])
    for i in range(rings - 2):
        for j in range(segments):
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            polygons.append([ring_vertex(a, b) for a, b in corners])
            textures.append([ring_uv(a, b) for a, b in corners])
    last = rings - 2
    for j in range(segments):
        polygons.append([south, ring_vertex(last, j + 1), ring_vertex(last, j)])
        south_uv = segments + (rings - 1) * (segments + 1) + j
        textures.append([south_uv, ring_uv(last, j + 1), ring_uv(last, j)])
    return vertices, polygons, textures, uv


def _fan(polygons: list[list[int]]) -> np.ndarray:
    return np.array([[p[0], p[k], p[k + 1]] for p in polygons for k in range(1, len(p) - 1)])


def open_tiny_mesh() -> tuple[np.ndarray, np.ndarray]:
    """A bumpy cap ~0.15 units across with two holes (open boundaries), like the bunny:
    vertices (N, 3) with N > 3000, faces (M, 3)."""
    sphere, faces = icosphere(5)
    keep_face = (sphere[faces].mean(axis=1) @ [0.0, 0.0, 1.0] > -0.4) & (
        sphere[faces].mean(axis=1) @ [0.6, 0.0, 0.8] < 0.93  # a second, small hole
    )
    faces = faces[keep_face]
    used = np.unique(faces)
    renumber = np.full(len(sphere), -1)
    renumber[used] = np.arange(len(used))
    vertices = _bumpy(sphere[used]) * 0.075  # ~0.15 units across
    return vertices, renumber[faces]


def huge_mesh() -> tuple[np.ndarray, np.ndarray]:
    """The default pebble scaled to ~30 units across, like the Ogre, on 3-decimal values."""
    vertices, faces = default_model(4)
    return np.round(vertices * 12.5, 3), faces


def write_obj(path: Path, vertices, polygons, textures=None, uv=None, normals: bool = False):
    """OBJ text written with Python's shortest round-trip floats (``repr``), so the arrays are
    exactly the file's values; ``normals`` adds ``vn`` records and ``v/vt/vn`` corners."""
    lines = ["# made by the GoGreen Sculpt tests", "o made"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices).tolist()]
    if uv is not None:
        lines += [f"vt {a!r} {b!r}" for a, b in np.asarray(uv).tolist()]
    if normals:
        lines.append("vn 0 0 1")
    lines.append("s 1")
    for k, polygon in enumerate(np.asarray(polygons, dtype=object).tolist()):
        if textures is None:
            corners = [str(i + 1) for i in polygon]
        else:
            tail = "/1" if normals else ""
            corners = [f"{i + 1}/{t + 1}{tail}" for i, t in zip(polygon, textures[k], strict=True)]
        lines.append("f " + " ".join(corners))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="session")
def made_textured(tmp_path_factory) -> MadeMesh:
    """Spot's stand-in: UV seams, vt and vn records, quads, ~2 units."""
    vertices, polygons, textures, uv = textured_seamed_mesh()
    path = tmp_path_factory.mktemp("made") / "textured.obj"
    write_obj(path, vertices, polygons, textures, uv, normals=True)
    return MadeMesh(path, vertices, _fan(polygons), uv, _fan(textures))


@pytest.fixture(scope="session")
def made_open_tiny(tmp_path_factory) -> MadeMesh:
    """The bunny's stand-in: open boundaries, ~0.15 units, more than 3000 vertices."""
    vertices, faces = open_tiny_mesh()
    path = tmp_path_factory.mktemp("made") / "open_tiny.obj"
    write_obj(path, vertices, faces)
    return MadeMesh(path, vertices, faces)


@pytest.fixture(scope="session")
def made_huge(tmp_path_factory) -> MadeMesh:
    """The Ogre's stand-in: ~30 units across."""
    vertices, faces = huge_mesh()
    path = tmp_path_factory.mktemp("made") / "huge.obj"
    write_obj(path, vertices, faces)
    return MadeMesh(path, vertices, faces)


@pytest.fixture(autouse=True)
def qt_work_ends():
    """After each test (pytest-qt has closed its widgets), wait for the app's background jobs
    (a panel's computation outlives the panel by up to a second), so that none runs on into
    the next test or past the end; then delete the closed widgets at once. Left to Qt, a
    closed window was deleted inside the next test's first wait (its window activation), in
    native code, beside that test's own window."""
    yield
    background = sys.modules.get("app.background")
    if background is not None:
        background.shared_pool().waitForDone(60_000)
    qt_core = sys.modules.get("PySide6.QtCore")
    if qt_core is not None and qt_core.QCoreApplication.instance() is not None:
        qt_core.QCoreApplication.sendPostedEvents(None, qt_core.QEvent.Type.DeferredDelete)


@pytest.fixture(autouse=True)
def state_home(tmp_path_factory, monkeypatch) -> Path:
    """Every test's ``XDG_STATE_HOME`` is a fresh temporary folder (inherited by the processes
    it starts), so that no crash-recovery journal (each open document writes one) ever lands in
    the user's ``~/.local/state``."""
    folder = tmp_path_factory.mktemp("state")
    monkeypatch.setenv("XDG_STATE_HOME", str(folder))
    return folder


# -- the main window (GUI tests) ---------------------------------------------------------------
@pytest.fixture
def app_look(qapp):
    """The application's style, palette and style sheet, restored after the test (the
    window applies its theme to the whole application)."""
    saved = qapp.palette(), qapp.styleSheet(), qapp.style().name(), qapp.property("gogreen_theme")
    yield qapp
    qapp.setStyle(saved[2])
    qapp.setPalette(saved[0])
    qapp.setStyleSheet(saved[1])
    qapp.setProperty("gogreen_theme", saved[3])


@pytest.fixture
def window(qtbot, tmp_path, monkeypatch, made_textured, app_look):
    """The main window on Spot's stand-in (UV seams), kernels ready, message boxes answered."""
    from gui_helpers import steps_done
    from PySide6.QtCore import QSettings
    from PySide6.QtWidgets import QMessageBox

    from app.main_window import MainWindow  # Qt only for the GUI tests that ask for it

    monkeypatch.setattr(QMessageBox, "warning", lambda *a, **k: QMessageBox.StandardButton.Ok)
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    win = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    # a running brush step would make the window refuse to close (it closes once the step
    # ends), and pytest-qt deletes it all the same: its viewport never closed
    qtbot.addWidget(win, before_close_func=lambda w: steps_done(w.viewport))
    win.show()
    qtbot.waitExposed(win)
    assert win.files.open_file(str(made_textured.path))  # Spot's stand-in: UV seams (conftest.py)
    assert win.kernel_warmer.wait(120_000)  # strokes are refused until the kernels are ready
    win.viewport.render()
    return win


@pytest.fixture(autouse=True)
def _influence_answers_checked():
    """Every influence test answered by the vertex blocks (``MeshState.rows_near``) is checked
    against the plain pass over every vertex, in every test: a path that writes vertices
    without reporting them fails the test that takes it."""
    from gogreen_core.mesh import influence

    saved, influence.VERIFY = influence.VERIFY, True
    influence.mismatches.clear()
    yield
    influence.VERIFY = saved
    found = list(influence.mismatches)
    influence.mismatches.clear()
    assert not found, f"rows_near missed or added rows: {found}"
