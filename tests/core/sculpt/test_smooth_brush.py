"""The smooth brush (and Shift-drag with any brush): less roughness, the same volume, only
within the brush's reach, an undo step that replays bit for bit."""

import json

import numpy as np
import pytest

import gogreen_core.sculpt.brushes.smooth as smooth_module
from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.interaction.tools import PointerEvent, SculptTools
from gogreen_core.mesh.geometry import mesh_volume, vertex_normals
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.mesh.topology import mesh_edges


@pytest.fixture(scope="module")
def noisy_sphere():
    """A unit icosphere (2,562 vertices) with 2 % radial noise."""
    vertices, faces = icosphere(4)
    rng = np.random.default_rng(1)
    return vertices * (1.0 + 0.02 * rng.standard_normal(len(vertices)))[:, None], faces


def roughness(vertices, faces):
    """RMS of the umbrella vector's normal part (x̄ − x)·n over the mean edge length."""
    ends = mesh_edges(faces, len(vertices)).ends
    n = len(vertices)
    around = np.zeros((n, 3))
    for a, b in ((0, 1), (1, 0)):
        for axis in range(3):
            around[:, axis] += np.bincount(ends[:, a], vertices[ends[:, b], axis], minlength=n)
    valence = np.bincount(ends.ravel(), minlength=n)
    umbrella = around / valence[:, None] - vertices
    normal_part = np.einsum("ij,ij->i", umbrella, vertex_normals(vertices, faces))
    edge = np.linalg.norm(vertices[ends[:, 0]] - vertices[ends[:, 1]], axis=1).mean()
    return float(np.sqrt(np.mean(normal_part**2)) / edge)


def smoothed(vertices, faces, events=10, **brush):
    sculptor = Sculptor(vertices, faces)
    brush = Brush("smooth", **{"radius": 0.2, "influence": np.inf, **brush})
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(brush, [BrushEvent(top, amount=1.0)] * events)
    return sculptor


def test_roughness_drops_and_the_volume_stays_within_1_percent(noisy_sphere):
    vertices, faces = noisy_sphere
    sculptor = smoothed(vertices, faces)
    before, after = roughness(vertices, faces), roughness(sculptor.vertices, faces)
    volume = mesh_volume(sculptor.vertices, faces) / mesh_volume(vertices, faces)
    # measured: roughness 0.266 → 0.05, volume −0.008 %
    assert after < 0.3 * before
    assert abs(volume - 1.0) < 0.01
    assert abs(volume - 1.0) < 0.001
    # a hundred more events: still within 1 %
    longer = smoothed(vertices, faces, events=100)
    assert abs(mesh_volume(longer.vertices, faces) / mesh_volume(vertices, faces) - 1.0) < 0.01


def test_the_mu_step_is_what_keeps_the_volume(noisy_sphere, monkeypatch):
    """Without the inflating μ step (plain Laplacian smoothing) the sphere shrinks: 4 % in
    ten events."""
    vertices, faces = noisy_sphere
    monkeypatch.setattr(smooth_module, "TAUBIN_MU", 0.0)
    plain = smoothed(vertices, faces)
    assert mesh_volume(plain.vertices, faces) / mesh_volume(vertices, faces) < 0.98


def test_only_the_brush_reach_moves_with_the_cutoff_weight(noisy_sphere):
    vertices, faces = noisy_sphere
    sculptor = Sculptor(vertices, faces)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(Brush("smooth", radius=0.05), [BrushEvent(top, amount=1.0)])
    moved = np.any(sculptor.vertices != vertices, axis=1)
    distance = np.linalg.norm(vertices - top, axis=1)
    outer = 4 * 0.05 * sculptor.model_size
    assert moved.sum() > 20 and not np.any(moved & (distance >= outer))
    assert sculptor.history.undo_labels == ["Smooth stroke"]
    assert sculptor.undo() == "Smooth stroke"
    assert np.array_equal(sculptor.vertices, vertices)
    # pressure (the amount) scales the step; no amount, no smoothing
    light = Sculptor(vertices, faces)
    light.apply_brush(Brush("smooth", radius=0.05), [BrushEvent(top, amount=0.0)])
    assert np.array_equal(light.vertices, vertices) and not light.history.can_undo


def test_open_rims_slide_along_themselves():
    """A noisy flat grid: the straight rim keeps its line (its two rim neighbours), the
    inside flattens."""
    n = 21
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    rng = np.random.default_rng(3)
    vertices = np.stack([x.ravel(), y.ravel(), 0.01 * rng.standard_normal(n * n)], axis=1)
    index = np.arange(n * n).reshape(n, n)
    quads = np.stack([index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]], axis=-1)
    quads = quads.reshape(-1, 4)
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    sculptor = smoothed(vertices, faces, events=5)
    left = index[0, 1:-1]  # the x = 0 rim without its corners
    assert np.all(sculptor.vertices[left, 0] == 0.0)
    inside = index[1:-1, 1:-1].ravel()
    assert np.std(sculptor.vertices[inside, 2]) < 0.5 * np.std(vertices[inside, 2])


def test_a_smooth_session_replays_bit_for_bit(noisy_sphere):
    vertices, faces = noisy_sphere
    sculptor = Sculptor(vertices, faces)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    events = [
        BrushEvent(top + np.array([0.02 * k, 0.0, 0.0]), [0.02, 0.0, 0.0], amount=0.7)
        for k in range(6)
    ]
    sculptor.apply_brush(Brush("smooth", radius=0.1, strength=2.5, symmetry="x"), events)
    session = json.loads(json.dumps(sculptor.session()))
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    mirror = again.vertices[:, 0] < -0.5
    assert np.any(again.vertices[mirror] != vertices[mirror])  # mirrored across x


def test_shift_drag_smooths_with_the_current_brush_radius(noisy_sphere):
    vertices, faces = noisy_sphere
    sculptor = Sculptor(vertices, faces)
    grab = Brush("grab", radius=0.07, influence=3.0)
    tools = SculptTools(sculptor, brush=lambda: grab)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    shift = frozenset({"shift"})
    tools.press(PointerEvent((100.0, 100.0), top, top, modifiers=shift))
    tools.move(PointerEvent((104.0, 100.0), top + np.array([0.02, 0.0, 0.0]), modifiers=shift))
    tools.flush()
    tools.release()
    stroke = sculptor.operations[-1]
    assert stroke.brush.kind == "smooth"
    assert (stroke.brush.radius, stroke.brush.influence) == (grab.radius, grab.influence)
    assert len(stroke.events) == 2  # the dab at the press and the move
    assert roughness(sculptor.vertices, faces) < roughness(vertices, faces)
    # without Shift the grab brush sculpts
    tools.press(PointerEvent((100.0, 100.0), top, top))
    tools.move(PointerEvent((104.0, 100.0), top + np.array([0.02, 0.0, 0.0])))
    tools.release()
    assert sculptor.operations[-1].brush == grab


@pytest.mark.parametrize("symmetry", ["", "xz"])
def test_paint_strokes_are_the_same_before_the_loops_are_compiled(noisy_sphere, symmetry):
    """Until numba has the paint loops (compiled in the background on a new machine) their
    NumPy twins run: the same smooth and mask strokes within 1e-12, open rims included."""
    from gogreen_core._compiled import forced

    vertices, faces = noisy_sphere
    keep = vertices[faces].mean(axis=1)[:, 2] > -0.5  # an open rim too
    faces = faces[keep]
    top = vertices[int(np.argmax(vertices[:, 2]))]
    events = [BrushEvent(top + k * np.array([0.05, 0.0, -0.02]), [0.05, 0.0, -0.02], amount=0.8)
              for k in range(8)]  # fmt: skip
    results = []
    for code in ("numpy", "unrolled"):
        with forced(code):
            sculptor = Sculptor(vertices, faces)
            sculptor.apply_brush(Brush("mask", radius=0.05, symmetry=symmetry), events[:2])
            brush = Brush("smooth", radius=0.15, strength=2.5, symmetry=symmetry)
            sculptor.apply_brush(brush, events)
            sculptor.apply_brush(Brush("smooth", radius=0.2, influence=np.inf), events[:1])
            results.append((sculptor.vertices.copy(), sculptor.mask.values.copy()))
    motion = float(np.abs(results[0][0] - vertices).max())
    assert motion > 0.0
    assert np.abs(results[0][0] - results[1][0]).max() <= 1e-12 * motion
    assert np.abs(results[0][1] - results[1][1]).max() <= 1e-12
