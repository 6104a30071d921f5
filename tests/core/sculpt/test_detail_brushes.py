"""The detail brushes (issue 34 item 3): Draw, Clay Strips, Crease, Flatten, Inflate, with
Blender's semantics, on made meshes (a flat sheet, a sphere): what each moves and which way,
Ctrl inverting, the mask, mirror symmetry, dab spacing, sessions and dynamic topology."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.geometry import vertex_normals
from gogreen_core.mesh.remesh import median_edge_length
from gogreen_core.mesh.shapes import flat_sheet, icosphere
from gogreen_core.mesh.topology import mesh_edges
from gogreen_core.sculpt.brushes.base import smooth_cutoff
from gogreen_core.sculpt.brushes.clay_strips import CLAY_OFFSET
from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, dab_offsets
from gogreen_core.sculpt.brushes.draw import DRAW_RATE
from gogreen_core.sculpt.brushes.flatten import CONTRAST_RATE
from gogreen_core.sculpt.engine_settings import EngineSettings

DETAIL = ("draw", "clay_strips", "crease", "flatten", "inflate")
RADIUS = 0.05  # ε in model sizes; the brush radius R is the automatic influence, 2 ε


@pytest.fixture(scope="module")
def sheet():
    """A flat 81 × 81 sheet over [-1, 1]² (model size 2√2), its normals along +z."""
    vertices, faces = flat_sheet(81)
    if vertex_normals(vertices, faces)[0, 2] < 0:
        faces = faces[:, ::-1].copy()
    return vertices, faces


@pytest.fixture(scope="module")
def sphere():
    return icosphere(4)  # unit sphere, 2,562 vertices, symmetric across x = 0


def brush_radius(sculptor: Sculptor, radius: float = RADIUS) -> float:
    return 2.0 * radius * sculptor.model_size


def dab(mesh, kind, center, amount=1.0, **brush):
    """A one-dab stroke (the press) of ``kind``: the sculptor after it."""
    sculptor = Sculptor(*mesh)
    sculptor.apply_brush(
        Brush(kind, **{"radius": RADIUS, **brush}), [BrushEvent(center, amount=amount)]
    )
    return sculptor


def stroke(mesh, kind, start, step, events, amount=1.0, settings=None, **brush):
    """A straight stroke: the press dab at ``start``, then ``events`` segments of ``step``."""
    sculptor = Sculptor(*mesh, settings=settings)
    brush = Brush(kind, **{"radius": RADIUS, **brush})
    start, step = np.asarray(start, float), np.asarray(step, float)
    moves = [BrushEvent(start + k * step, step, amount=amount) for k in range(events)]
    sculptor.apply_brush(brush, [BrushEvent(start, amount=amount), *moves])
    return sculptor


def test_draw_moves_along_the_area_normal_by_the_falloff_and_ctrl_carves(sheet):
    vertices, _ = sheet
    center = np.zeros(3)
    drawn = dab(sheet, "draw", center)
    radius = brush_radius(drawn)
    motion = drawn.vertices - vertices
    distance = np.linalg.norm(vertices - center, axis=1)
    expected = DRAW_RATE * DAB_SPACING * radius * smooth_cutoff(distance, 0.0, radius)
    assert np.all(motion[:, :2] == 0.0)  # along the sheet's normal alone
    np.testing.assert_allclose(motion[:, 2], expected, rtol=1e-12, atol=1e-15)
    assert np.all(motion[distance >= radius] == 0.0) and motion[:, 2].max() > 0
    carved = dab(sheet, "draw", center, amount=-1.0)  # Ctrl: the same motion inwards
    np.testing.assert_allclose(carved.vertices - vertices, -motion, rtol=1e-12, atol=1e-15)
    half = dab(sheet, "draw", center, amount=0.5, strength=2.0)  # strength × pressure
    np.testing.assert_allclose(half.vertices - vertices, motion, rtol=1e-12, atol=1e-15)


def test_draw_moves_every_vertex_one_way_and_inflate_each_along_its_normal(sphere):
    vertices, faces = sphere
    top = vertices[int(np.argmax(vertices[:, 2]))]
    normals = vertex_normals(vertices, faces)
    for kind in ("draw", "inflate"):
        for amount in (1.0, -1.0):
            sculptor = dab(sphere, kind, top, amount=amount, radius=0.15)
            motion = sculptor.vertices - vertices
            moved = np.flatnonzero(np.linalg.norm(motion, axis=1) > 0)
            assert len(moved) > 30
            unit = motion[moved] / np.linalg.norm(motion[moved], axis=1)[:, None]
            if kind == "draw":  # one direction: the area normal, here the top's +z
                assert np.all(np.abs(unit @ [0.0, 0.0, amount]) > 1 - 1e-12)
            else:  # each along its own normal: the radius grows (Ctrl: shrinks) locally
                along = np.einsum("ij,ij->i", unit, normals[moved])
                assert np.all(along * amount > 0.999)
                radii = np.linalg.norm(sculptor.vertices[moved], axis=1)
                assert np.all((radii - 1.0) * amount > 0)
                assert np.all(np.linalg.norm(sculptor.vertices, axis=1)[moved] != 1.0)
            far = np.linalg.norm(vertices - top, axis=1) >= brush_radius(sculptor, 0.15)
            assert np.all(motion[far] == 0.0)


def test_clay_strips_reach_their_plane_and_never_pass_it(sheet):
    vertices, _ = sheet
    center = np.zeros(3)
    for amount in (1.0, -1.0):
        # a strength that takes the plateau all the way to the plane in one dab
        sculptor = dab(sheet, "clay_strips", center, amount=amount, strength=50.0)
        plane = amount * CLAY_OFFSET * brush_radius(sculptor)
        heights = sculptor.vertices[:, 2]
        assert np.all(amount * heights <= abs(plane) * (1 + 1e-12))  # never past the plane
        assert np.isclose(heights[np.argmin(np.linalg.norm(vertices, axis=1))], plane)
        assert np.sum(np.isclose(heights, plane, rtol=1e-12)) > 20  # a flat top
        assert np.all(sculptor.vertices[:, :2] == vertices[:, :2])  # along the normal only
    # a whole stroke builds up without overshooting any dab's plane: never more than the
    # plane above the highest point a dab has seen
    built = stroke(sheet, "clay_strips", [-0.3, 0.0, 0.0], [0.02, 0.0, 0.0], 30, strength=5.0)
    assert 0 < built.vertices[:, 2].max()
    assert built.vertices[:, 2].max() <= 30 * CLAY_OFFSET * brush_radius(built)


@pytest.mark.parametrize("direction", [(1.0, 0.0), (1.0, 1.0)])
def test_clay_strips_footprint_is_a_square_along_the_stroke(sheet, direction):
    vertices, _ = sheet
    along = np.array([*direction, 0.0]) / np.linalg.norm(direction)
    across = np.cross([0.0, 0.0, 1.0], along)
    # the stroke's first event: a dab at its start, facing its way (shorter than the spacing)
    sculptor = Sculptor(*sheet)
    sculptor.apply_brush(
        Brush("clay_strips", radius=RADIUS), [BrushEvent(np.zeros(3), 1e-4 * along, amount=1.0)]
    )
    radius = brush_radius(sculptor)
    moved = vertices[sculptor.vertices[:, 2] != 0.0]
    u, v = moved @ along, moved @ across
    assert np.all(np.maximum(np.abs(u), np.abs(v)) < radius)  # within the square
    corner = (np.abs(u) > 0.5 * radius) & (np.abs(v) > 0.5 * radius)
    assert np.any(np.hypot(u, v)[corner] > 1.2 * radius)  # into its corners, past a circle's


def test_crease_carves_and_pinches_towards_the_stroke_line(sheet):
    vertices, _ = sheet
    for amount in (1.0, -1.0):
        sculptor = stroke(sheet, "crease", [-0.4, 0.0, 0.0], [0.05, 0.0, 0.0], 16, amount=amount)
        motion = sculptor.vertices - vertices
        middle = (np.abs(vertices[:, 0]) < 0.2) & (np.abs(vertices[:, 1]) > 0.01)
        middle &= np.abs(vertices[:, 1]) < 0.5 * brush_radius(sculptor)
        # pinched: every vertex beside the line comes closer to it, whichever way it draws
        assert np.all(np.abs(sculptor.vertices[middle, 1]) < np.abs(vertices[middle, 1]))
        # towards the line, not along it (the dabs before and after pinch along it alike)
        assert np.abs(motion[middle, 0]).max() < 0.2 * np.abs(motion[middle, 1]).max()
        # drawn: inwards (a groove), outwards with Ctrl (a ridge)
        assert np.all(-amount * motion[middle, 2] > 0)


def test_flatten_levels_towards_the_area_plane_and_ctrl_adds_contrast(sheet):
    vertices, faces = sheet
    bumpy = vertices.copy()
    bumpy[:, 2] = 0.02 * np.cos(9 * vertices[:, 0]) * np.cos(9 * vertices[:, 1])
    mesh = (bumpy, faces)
    near = np.linalg.norm(vertices[:, :2], axis=1) < 0.1

    def spread(s: Sculptor) -> float:
        points = s.vertices[near]
        centred = points - points.mean(axis=0)
        return float(np.linalg.eigvalsh(centred.T @ centred)[0])  # off its best plane

    flat = stroke(mesh, "flatten", [-0.2, 0.0, 0.0], [0.02, 0.0, 0.0], 20)
    contrast = stroke(mesh, "flatten", [-0.2, 0.0, 0.0], [0.02, 0.0, 0.0], 20, amount=-1.0)
    before = spread(Sculptor(*mesh))
    assert spread(flat) < 0.2 * before
    assert spread(contrast) > 1.5 * before
    # contrast pushes the farther the more, but a pass at most CONTRAST_RATE R (strength 1)
    strong = stroke(mesh, "flatten", [-0.2, 0.0, 0.0], [0.02, 0.0, 0.0], 20, amount=-1.0,
                    strength=10.0)  # fmt: skip
    most = 10.0 * CONTRAST_RATE * brush_radius(strong)
    assert np.abs(strong.vertices - bumpy).max() <= most


@pytest.mark.parametrize("kind", DETAIL)
def test_a_held_vertex_does_not_move(sphere, kind):
    vertices, _ = sphere
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor = Sculptor(*sphere)
    held = vertices[:, 0] > 0
    sculptor.mask.adopt(held.astype(float))
    sculptor.apply_brush(
        Brush(kind, radius=0.15), [BrushEvent(top, amount=1.0), BrushEvent(top, [0.1, 0, 0])]
    )
    moved = np.any(sculptor.vertices != vertices, axis=1)
    assert not np.any(moved & held) and np.any(moved & ~held)


@pytest.mark.parametrize("kind", DETAIL)
def test_mirror_symmetry_moves_the_mirror_image_the_mirrored_way(sphere, kind):
    vertices, _ = sphere
    mirror = np.array([[-1.0, 1.0, 1.0]])
    key = {tuple(np.round(p, 9)): i for i, p in enumerate(vertices)}
    image = np.array([key[tuple(np.round(p, 9))] for p in vertices * mirror])
    start = np.array([0.6, 0.0, 0.8])
    sculptor = stroke(sphere, kind, start, [0.0, 0.05, 0.0], 6, radius=0.1, symmetry="x")
    motion = sculptor.vertices - vertices
    assert np.abs(motion[vertices[:, 0] < -0.3]).max() > 1e-3  # the other side moved too
    np.testing.assert_allclose(motion[image] * mirror, motion, atol=1e-12)


@pytest.mark.parametrize("kind", DETAIL)
def test_how_fast_the_mouse_reports_does_not_change_the_stroke(sheet, kind):
    """The dabs fall every DAB_SPACING of the radius along the stroke, however it is cut."""
    vertices, faces = sheet
    bumpy = vertices.copy()
    bumpy[:, 2] = 0.02 * np.cos(9 * vertices[:, 0])
    mesh = (bumpy, faces)
    coarse = stroke(mesh, kind, [-0.3, 0.0, 0.0], [0.15, 0.0, 0.0], 4)
    fine = stroke(mesh, kind, [-0.3, 0.0, 0.0], [0.015, 0.0, 0.0], 40)
    assert np.abs(coarse.vertices - bumpy).max() > 1e-3
    np.testing.assert_allclose(fine.vertices, coarse.vertices, atol=1e-9)


def test_dab_offsets_carry_the_spacing_between_events():
    at, left = dab_offsets(0.0, 0.1, None)  # the press: a dab where it is
    assert at.tolist() == [0.0] and left == 0.0
    at, left = dab_offsets(0.25, 0.1, 0.0)
    np.testing.assert_allclose(at, [0.1, 0.2]) and np.isclose(left, 0.05)
    at, left2 = dab_offsets(0.03, 0.1, left)  # not yet the next dab
    assert len(at) == 0 and np.isclose(left2, 0.08)
    at, _ = dab_offsets(1e3, 1e-6, 0.0)  # capped: at most MAX_DABS, spread along
    assert len(at) <= 256 and at[-1] > 990


@pytest.mark.parametrize("kind", DETAIL)
def test_a_session_replays_bit_for_bit(sphere, kind):
    vertices, faces = sphere
    sculptor = stroke(
        sphere, kind, [0.3, 0.2, 0.9], [0.03, -0.02, 0.0], 8, amount=0.7, radius=0.08,
        symmetry="x", strength=1.5,
    )  # fmt: skip
    assert np.any(sculptor.vertices != vertices)
    session = json.loads(json.dumps(sculptor.session()))
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    sculptor.undo()
    assert np.array_equal(sculptor.vertices, vertices)


def test_the_recovery_journal_brings_back_every_detail_stroke(sphere, tmp_path):
    from gogreen_core.files.journal import Journal
    from gogreen_core.files.recovery import recover
    from gogreen_core.mesh.mesh_io import MeshData

    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    journal = Journal(sculptor, MeshData(vertices=vertices, faces=faces), root=tmp_path)
    for k, kind in enumerate(DETAIL):
        start = np.array([0.2 * k - 0.4, -0.3, 0.9])
        brush = Brush(kind, radius=0.06, symmetry="x" if k % 2 else "")
        events = [BrushEvent(start, amount=1.0)]
        events += [
            BrushEvent(start + np.array([0, 0.03 * i, 0]), [0, 0.03, 0], amount=-0.6)
            for i in range(5)
        ]
        sculptor.apply_brush(brush, events)
    sculptor.undo()
    journal.flush()
    directory = journal.directory
    journal.close(remove=False)  # as a killed process leaves it
    recovered = recover(directory, budget=float("inf")).sculptor
    assert np.array_equal(recovered.vertices, sculptor.vertices)
    assert recovered.history.undo_labels == sculptor.history.undo_labels
    for s in (sculptor, recovered):
        s.redo()
    assert np.array_equal(recovered.vertices, sculptor.vertices)
    assert sculptor.history.undo_labels[-1] == "Inflate stroke"


def test_draw_with_dynamic_topology_keeps_edges_within_bounds(sphere):
    vertices, faces = sphere
    median = median_edge_length(vertices, faces)
    settings = EngineSettings(dynamic_topology=True)
    fixed = stroke(sphere, "draw", [0.0, -0.3, 0.95], [0.0, 0.04, 0.0], 15, strength=20.0)
    dynamic = stroke(
        sphere, "draw", [0.0, -0.3, 0.95], [0.0, 0.04, 0.0], 15, strength=20.0, settings=settings
    )
    assert len(dynamic.vertices) > len(vertices)  # split where the draw stretched it

    def longest(s: Sculptor) -> float:
        ends = mesh_edges(s.faces, len(s.vertices)).ends
        return float(np.linalg.norm(s.vertices[ends[:, 0]] - s.vertices[ends[:, 1]], axis=1).max())

    assert longest(fixed) > 2.0 * median  # what the draw does to fixed faces
    assert longest(dynamic) <= 2.0 * median
    assert np.all(mesh_edges(dynamic.faces, len(dynamic.vertices)).face_count == 2)  # closed
    assert dynamic.vertices[:, 2].max() > 1.0 + 0.5 * (fixed.vertices[:, 2].max() - 1.0)
    # its undo step holds what the draw changed (a local brush: a small part of the mesh)
    whole = 2 * (vertices.nbytes + faces.nbytes)
    assert dynamic.history.memory_bytes < 0.25 * whole
    after = dynamic.vertices.copy(), dynamic.faces.copy()
    dynamic.undo()
    assert np.array_equal(dynamic.vertices, vertices) and np.array_equal(dynamic.faces, faces)
    dynamic.redo()
    assert np.array_equal(dynamic.vertices, after[0]) and np.array_equal(dynamic.faces, after[1])
