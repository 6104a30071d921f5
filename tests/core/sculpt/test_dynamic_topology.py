"""Dynamic topology (issue 34): the stroke remeshes what it moves (gogreen_core.mesh.remesh), and
Mesh → Remesh."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from scipy.spatial import cKDTree

import gogreen_core.mesh.remesh as remesh_module
import gogreen_core.sculpt.stroke as stroke_module
from gogreen_core import Sculptor
from gogreen_core.mesh.mesh_state import MaskRows
from gogreen_core.mesh.remesh import (
    closest_points_on_triangles,
    median_edge_length,
    remesh,
    smallest_angles,
)
from gogreen_core.mesh.shapes import default_model, icosphere, open_tube
from gogreen_core.mesh.subdivision import loop_subdivide
from gogreen_core.mesh.topology import mesh_edges
from gogreen_core.physics.material import Material
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.validation import ParameterError

CUBIC = Material.cubic(3.0, 1.5, 0.4)
PULL_EVENTS, PULL_STEP, PULL_RADIUS = 20, 0.02, 0.03


# -- helpers -------------------------------------------------------------------------------------
def euler_and_check(vertices: np.ndarray, faces: np.ndarray) -> int:
    """The Euler characteristic of a closed, consistently oriented 2-manifold (asserted)."""
    edges = mesh_edges(faces, len(vertices))
    assert np.all(edges.face_count == 2), "not closed, or not a manifold"
    following = np.roll(faces, -1, axis=1)
    directed = faces.ravel() * len(vertices) + following.ravel()
    assert len(np.unique(directed)) == len(directed), "faces not consistently oriented"
    used = np.zeros(len(vertices), dtype=bool)
    used[faces.ravel()] = True
    assert used.all(), "a vertex in no face"
    return len(vertices) - len(edges) + len(faces)


def edge_lengths(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    ends = mesh_edges(faces, len(vertices)).ends
    return np.linalg.norm(vertices[ends[:, 1]] - vertices[ends[:, 0]], axis=1)


def distance_to_surface(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Each point's distance to the triangles (the 64 whose centroids are nearest)."""
    tree = cKDTree(vertices[faces].mean(axis=1))
    _, candidates = tree.query(points, k=64)
    best = np.full(len(points), np.inf)
    for column in candidates.T:
        corners = vertices[faces[column]]
        near, _ = closest_points_on_triangles(points, corners[:, 0], corners[:, 1], corners[:, 2])
        best = np.minimum(best, np.linalg.norm(near - points, axis=1))
    return best


def pull(sculptor: Sculptor, events: int = PULL_EVENTS) -> None:
    """Grab the top vertex and pull it out along +z (the normal there)."""
    vertices = sculptor.vertices
    center = vertices[int(np.argmax(vertices[:, 2]))].copy()
    step = np.array([0.0, 0.0, PULL_STEP * sculptor.model_size])
    sculptor.begin_stroke(Brush("grab", radius=PULL_RADIUS))
    for _ in range(events):
        sculptor.stroke_event(BrushEvent(center=center, delta=step))
        center = center + step
    sculptor.end_stroke()


@pytest.fixture(scope="module")
def pulls() -> dict[str, object]:
    vertices, faces = default_model()
    fixed = Sculptor(vertices, faces, settings=EngineSettings(material=CUBIC))
    pull(fixed)
    dynamic = Sculptor(
        vertices, faces, settings=EngineSettings(material=CUBIC, dynamic_topology=True)
    )
    pull(dynamic)
    return {
        "vertices": vertices,
        "faces": faces,
        "fixed": (fixed.vertices.copy(), fixed.faces.copy()),
        "dynamic": (dynamic.vertices.copy(), dynamic.faces.copy()),
        "sculptor": dynamic,
        "size": dynamic.model_size,
    }


# -- the pull on the default model ----------------------------------------------------------------
def test_the_pull_keeps_its_edges_near_the_surfaces_own(pulls):
    median = median_edge_length(pulls["vertices"], pulls["faces"])
    assert edge_lengths(*pulls["dynamic"]).max() <= 2.0 * median
    assert edge_lengths(*pulls["fixed"]).max() > 10.0 * median  # what it was without


def spike_angles(pulls, which: str) -> np.ndarray:
    vertices, faces = pulls[which]
    top = pulls["vertices"][:, 2].max()
    length = PULL_EVENTS * PULL_STEP * pulls["size"]
    spike = vertices[faces].mean(axis=1)[:, 2] > top + 0.1 * length
    assert spike.sum() > 50
    return smallest_angles(vertices[faces[spike]])


def test_the_spike_is_made_of_well_shaped_triangles(pulls):
    assert np.mean(spike_angles(pulls, "dynamic") >= 20.0) >= 0.99
    assert np.mean(spike_angles(pulls, "fixed") >= 20.0) < 0.9


def test_the_pulled_mesh_stays_a_closed_oriented_manifold_without_degenerate_faces(pulls):
    vertices, faces = pulls["dynamic"]
    before = euler_and_check(pulls["vertices"], pulls["faces"])
    assert euler_and_check(vertices, faces) == before
    median = median_edge_length(pulls["vertices"], pulls["faces"])
    corners = vertices[faces]
    doubled = np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    assert doubled.min() > 1e-3 * median**2
    assert smallest_angles(corners).min() > 5.0


def test_the_pull_lands_where_the_fixed_topology_pull_does(pulls):
    length = PULL_EVENTS * PULL_STEP * pulls["size"]
    fixed, dynamic = pulls["fixed"][0], pulls["dynamic"][0]
    tip_fixed = fixed[np.argmax(fixed[:, 2])]
    tip_dynamic = dynamic[np.argmax(dynamic[:, 2])]
    assert np.linalg.norm(tip_dynamic - tip_fixed) <= 0.03 * length
    median = median_edge_length(pulls["vertices"], pulls["faces"])
    gap = distance_to_surface(dynamic, *pulls["fixed"])
    assert gap.max() <= median


def test_one_undo_gives_back_the_mesh_bit_for_bit(pulls):
    """... and the step holds what the stroke changed, not the meshes before and after it: the
    grab's far field moves every vertex (their positions are kept, as a fixed-topology stroke's
    are), its remeshing touched about 40 % of the faces."""
    sculptor = pulls["sculptor"]
    vertices, faces = pulls["vertices"], pulls["faces"]
    whole = 2 * (vertices.nbytes + faces.nbytes // 2 + vertices.nbytes // 3)  # int32 faces
    assert sculptor.history.memory_bytes < 0.8 * whole
    for _ in range(2):
        assert sculptor.undo() == "Wide grab stroke"
        assert np.array_equal(sculptor.vertices, vertices)
        assert np.array_equal(sculptor.faces, faces)
        assert sculptor.faces.dtype == np.int64 and not sculptor.mask.values.any()
        sculptor.redo()
        assert np.array_equal(sculptor.vertices, pulls["dynamic"][0])
        assert np.array_equal(sculptor.faces, pulls["dynamic"][1])


# -- what the remesh carries over ----------------------------------------------------------------
def textured_sphere() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """An icosphere with texture corners per face: faces with x > 0 use the chart (y, z), the
    others (y + 10, z), so the vertices where they meet are on a seam; a mask 0.2 + 0.1 x."""
    vertices, faces = icosphere(3)
    east = vertices[faces].mean(axis=1)[:, 0] > 0
    uv = np.concatenate([vertices[:, 1:], vertices[:, 1:] + [10.0, 0.0]])
    uv_faces = np.where(east[:, None], faces, faces + len(vertices))
    uv_faces[:3] = -1  # a few faces without texture
    mask = 0.2 + 0.1 * vertices[:, 0]
    return vertices, faces, uv, uv_faces, mask


@pytest.mark.parametrize("scale", [0.55, 1.7])
def test_texture_corners_and_the_mask_are_interpolated_and_seams_stay(scale):
    vertices, faces, uv, uv_faces, mask = textured_sphere()
    target = scale * median_edge_length(vertices, faces)
    done = remesh(
        vertices, faces, np.ones(len(vertices), bool), target, mask=mask, uv=uv, uv_faces=uv_faces
    )
    assert len(done.faces) != len(faces)
    euler_and_check(done.vertices, done.faces)
    # everything made by midpoints and barycentric interpolation on the surface: still linear
    assert np.allclose(done.mask, 0.2 + 0.1 * done.vertices[:, 0], atol=1e-12)
    textured = done.uv_faces[:, 0] >= 0
    assert (~textured).sum() >= 1
    corner_uv = done.uv[done.uv_faces[textured]]  # (K, 3, 2)
    corner_xyz = done.vertices[done.faces[textured]]
    chart = np.where(corner_uv[:, :, 0] > 5.0, 10.0, 0.0)
    assert np.allclose(corner_uv[:, :, 0] - chart, corner_xyz[:, :, 1], atol=1e-9)
    assert np.allclose(corner_uv[:, :, 1], corner_xyz[:, :, 2], atol=1e-9)
    assert np.all(chart == chart[:, :1])  # one chart per face: the seam is still a seam
    # the seam's vertices (in faces of both charts) lie on the old seam's edges
    seam = np.zeros(len(done.vertices), dtype=int)
    for value, bit in ((0.0, 1), (10.0, 2)):
        np.bitwise_or.at(seam, done.faces[textured][chart[:, 0] == value].ravel(), bit)
    on_seam = done.vertices[seam == 3]
    assert len(on_seam) >= 10
    old = mesh_edges(faces, len(vertices))
    east = vertices[faces].mean(axis=1)[:, 0] > 0
    sides = np.zeros(len(old), dtype=int)
    np.bitwise_or.at(sides, old.face_edges[east].ravel(), 1)
    np.bitwise_or.at(sides, old.face_edges[~east].ravel(), 2)
    a, b = (vertices[old.ends[sides == 3, k]] for k in (0, 1))
    t = np.clip(
        np.einsum("pij,ij->pi", on_seam[:, None] - a, b - a) / np.sum((b - a) ** 2, 1), 0, 1
    )
    gap = np.linalg.norm(a + t[:, :, None] * (b - a) - on_seam[:, None], axis=2).min(axis=1)
    assert gap.max() < 1e-12


def test_locked_vertices_rims_and_the_outside_stay_bit_for_bit():
    vertices, faces = open_tube(rings=40, around=24, length=6.0)
    n = len(vertices)
    region = np.abs(vertices[:, 2]) < 2.0
    region |= vertices[:, 2] < -2.9  # the rim at the bottom
    locked = np.zeros(n, bool)
    locked[np.flatnonzero(region & (np.abs(vertices[:, 2]) < 1.0))[::7]] = True
    target = 0.5 * median_edge_length(vertices, faces)
    done = remesh(vertices, faces, region, target, locked=locked)
    assert len(done.vertices) > n
    keep = done.kept >= 0
    assert np.all(keep[~region]) and np.all(keep[locked])
    stay = ~region | locked
    assert np.array_equal(done.vertices[done.kept[stay]], vertices[stay])

    def rim(v: np.ndarray, f: np.ndarray) -> set[tuple[int, int]]:
        edges = mesh_edges(f, len(v))
        return {(int(p), int(q)) for p, q in edges.ends[edges.face_count == 1]}

    old_rim = {tuple(sorted(int(done.kept[i]) for i in e)) for e in rim(vertices, faces)}
    assert rim(done.vertices, done.faces) == old_rim
    assert np.all(~done.changed[done.kept[~region]])


def test_pins_are_never_collapsed_away_nor_moved(monkeypatch):
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces, settings=EngineSettings(dynamic_topology=True))
    top = int(np.argmax(vertices[:, 2]))
    near_top = np.argsort(np.linalg.norm(vertices - vertices[top], axis=1))[3:30:6]
    for row in near_top:
        sculptor.add_constraint(vertices[row])
    calls = []
    real = stroke_module.remesh

    def spy(points, f, region, length, **options):
        done = real(points, f, region, length, **options)
        held = np.flatnonzero(options["locked"])
        # the vertex nearest each pin (the grab moves them: two pins may share one)
        gaps = points[None, :, :] - sculptor.constraint_points[:, None, :]
        nearest = np.unique(np.argmin(np.einsum("pij,pij->pi", gaps, gaps), axis=1))
        calls.append(np.array_equal(held, nearest))
        assert np.all(done.kept[held] >= 0)
        assert np.array_equal(done.vertices[done.kept[held]], points[held])
        return done

    monkeypatch.setattr(stroke_module, "remesh", spy)
    points = sculptor.constraint_points.copy()
    pull(sculptor, events=6)
    assert calls and all(calls)
    assert np.array_equal(sculptor.constraint_points, points)
    assert len(sculptor.faces) != len(faces)


# -- sessions, cancel, settings ------------------------------------------------------------------
def test_a_pull_by_the_fine_part_leaves_the_coarse_part_coarse(monkeypatch):
    """``detail_size=None`` keeps each place's own edge length (issue 34): on a sphere fine on
    one side (x > 0, edges 4x shorter) and coarse on the other, a pull on the fine side by the
    boundary remeshes the coarse faces it strains at their coarse length; it does not refine
    the coarse side to the fine side's edges (a single target length did: 289 coarse vertices
    became 4,786 and the mesh doubled), and each event's region stays about the last one's
    (it was 5x every other event)."""
    vertices, faces = two_part_sphere()

    def coarse_edges(v: np.ndarray, f: np.ndarray) -> np.ndarray:
        ends = mesh_edges(f, len(v)).ends
        inside = np.all(v[ends][:, :, 0] < -0.1, axis=1)
        return np.linalg.norm(v[ends[inside, 1]] - v[ends[inside, 0]], axis=1)

    before = coarse_edges(vertices, faces)
    assert np.median(before) > 3.0 * median_edge_length(vertices, faces)
    regions = []
    real = stroke_module.remesh

    def spy(points, f, region, length, **options):
        regions.append(int(region.sum()))
        return real(points, f, region, length, **options)

    monkeypatch.setattr(stroke_module, "remesh", spy)
    sculptor = Sculptor(
        vertices, faces, settings=EngineSettings(material=CUBIC, dynamic_topology=True)
    )
    direction = np.array([0.12, 0.0, 1.0]) / np.linalg.norm([0.12, 0.0, 1.0])
    center = vertices[int(np.argmax(vertices @ direction))].copy()
    step = 0.02 * sculptor.model_size * direction
    sculptor.begin_stroke(Brush("grab", radius=0.08))
    for _ in range(10):
        sculptor.stroke_event(BrushEvent(center=center, delta=step))
        center = center + step
    sculptor.end_stroke()
    pulled, cells = sculptor.vertices, sculptor.faces
    assert len(cells) != len(faces)  # remeshed
    euler_and_check(pulled, cells)
    after = coarse_edges(pulled, cells)
    assert np.median(after) >= 0.8 * np.median(before)
    assert len(after) <= 1.25 * len(before)
    assert len(pulled) <= 1.2 * len(vertices)
    assert len(regions) == 10
    assert all(now <= 1.5 * last for last, now in itertools.pairwise(regions))


def test_a_session_with_dynamic_topology_and_a_remesh_replays_bit_for_bit():
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces, settings=EngineSettings(material=CUBIC))
    sculptor.change_settings(dynamic_topology=True, detail_size=0.02)
    pull(sculptor, events=5)
    sculptor.change_settings(dynamic_topology=True, detail_size=None)
    pull(sculptor, events=4)
    sculptor.undo()
    sculptor.redo()
    sculptor.remesher.remesh(0.03, iterations=2)
    session = json.loads(json.dumps(sculptor.session()))
    ops = [op["op"] for op in session["operations"]]
    assert ops.count("dynamic_topology") == 2 and "remesh" in ops
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert np.array_equal(again.faces, sculptor.faces)
    assert again.settings == sculptor.settings
    for _ in range(4):  # remesh, stroke, stroke, the setting
        again.undo()
    assert again.settings.dynamic_topology and again.settings.detail_size == 0.02
    again.undo()
    again.undo()
    assert np.array_equal(again.vertices, vertices) and np.array_equal(again.faces, faces)
    assert not again.settings.dynamic_topology


def test_a_cancelled_stroke_puts_the_mesh_back():
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces, settings=EngineSettings(dynamic_topology=True))
    sculptor.begin_stroke(Brush("grab", radius=PULL_RADIUS))
    top = vertices[int(np.argmax(vertices[:, 2]))]
    for k in range(4):
        step = np.array([0.0, 0.0, 0.03 * sculptor.model_size])
        sculptor.stroke_event(BrushEvent(center=top + k * step, delta=step))
    assert len(sculptor.faces) != len(faces)
    sculptor.cancel_stroke()
    assert np.array_equal(sculptor.vertices, vertices) and np.array_equal(sculptor.faces, faces)
    assert not sculptor.history.can_undo


def two_part_sphere() -> tuple[np.ndarray, np.ndarray]:
    """An icosphere fine on one side (x > -0.05, edges 4x shorter), coarse on the other."""
    vertices, faces = icosphere(3)
    for _ in range(2):
        fine = np.all(vertices[faces][:, :, 0] > -0.05, axis=1)
        done = loop_subdivide(vertices, faces, refine=fine)
        vertices, faces = done.vertices, done.faces
    return vertices, faces


def test_mesh_remesh_without_a_detail_size_keeps_each_parts_own_edges():
    """Remesh with ``detail_size=None`` keeps each vertex's own edge length (issue 34): the
    vertex count stays near the input's (one length for the whole mesh, the median, refined
    the coarse side: 4.6M vertices from the 1M-vertex ogre), the coarse side stays coarse, the
    fine side fine; undo and a replayed session give the arrays back bit for bit."""
    vertices, faces = two_part_sphere()
    sculptor = Sculptor(vertices, faces)
    chi = euler_and_check(vertices, faces)
    sculptor.remesher.remesh(None)
    after_v, after_f = sculptor.vertices.copy(), sculptor.faces.copy()
    assert euler_and_check(after_v, after_f) == chi
    assert 0.8 * len(vertices) <= len(after_v) <= 1.2 * len(vertices)

    def side_medians(v: np.ndarray, f: np.ndarray) -> tuple[float, float]:
        ends = mesh_edges(f, len(v)).ends
        length = np.linalg.norm(v[ends[:, 1]] - v[ends[:, 0]], axis=1)
        x = v[ends].mean(axis=1)[:, 0]
        return float(np.median(length[x < -0.3])), float(np.median(length[x > 0.3]))

    coarse, fine = side_medians(vertices, faces)
    coarse_after, fine_after = side_medians(after_v, after_f)
    assert 0.75 * coarse < coarse_after < 1.25 * coarse
    assert 0.75 * fine < fine_after < 1.25 * fine
    assert smallest_angles(after_v[after_f]).min() > 5.0
    session = json.loads(json.dumps(sculptor.session()))
    replayed = Sculptor.from_session(session, vertices, faces)
    replayed.replay(session["operations"])
    assert np.array_equal(replayed.vertices, after_v) and np.array_equal(replayed.faces, after_f)
    assert sculptor.undo() == "remesh"
    assert np.array_equal(sculptor.vertices, vertices) and np.array_equal(sculptor.faces, faces)


def test_mesh_remesh_makes_edges_the_detail_size_and_undoes_exactly():
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces)
    chi = euler_and_check(vertices, faces)
    size = 0.6 * median_edge_length(vertices, faces) / sculptor.model_size
    sculptor.remesher.remesh(size)
    target = size * sculptor.model_size
    lengths = edge_lengths(sculptor.vertices, sculptor.faces) / target
    assert 0.85 < np.median(lengths) < 1.15
    assert lengths.max() <= 4.0 / 3.0 + 1e-9
    assert euler_and_check(sculptor.vertices, sculptor.faces) == chi
    assert sculptor.undo() == "remesh"
    assert np.array_equal(sculptor.vertices, vertices) and np.array_equal(sculptor.faces, faces)


def test_remesh_of_the_unmasked_part_leaves_the_masked_part_alone():
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces)
    held = vertices[:, 0] > 0.2
    sculptor._mesh.set_mask_rows(MaskRows(np.flatnonzero(held), np.ones(held.sum())))
    sculptor.remesher.remesh(0.5 * median_edge_length(vertices, faces) / sculptor.model_size, True)
    assert len(sculptor.vertices) > len(vertices)
    mask = sculptor.mesh.mask
    kept_held = sculptor.vertices[mask == 1.0]
    assert len(kept_held) == held.sum()
    assert np.array_equal(np.sort(kept_held, axis=0), np.sort(vertices[held], axis=0))


@pytest.mark.parametrize(
    ("changes", "parameter"),
    [({"detail_size": 0.0}, "detail_size"), ({"detail_size": 1.0}, "detail_size"),
     ({"dynamic_topology": 1}, "dynamic_topology")],
)  # fmt: skip
def test_bad_settings_are_refused_by_name(changes, parameter):
    with pytest.raises(ParameterError) as info:
        EngineSettings(**changes)
    assert info.value.parameter == parameter


def test_settings_round_trip_and_old_files_stay_as_they_were():
    assert "dynamic_topology" not in EngineSettings().to_dict()
    settings = EngineSettings(dynamic_topology=True, detail_size=0.01)
    data = json.loads(json.dumps(settings.to_dict()))
    assert EngineSettings.from_dict(data) == settings
    with pytest.raises(ParameterError, match="detail_size"):
        Sculptor(*icosphere(2)).remesher.remesh(float("nan"))


# -- mirror symmetry ------------------------------------------------------------------------------
def test_a_mirrored_pull_stays_mirror_symmetric_to_within_an_edge():
    """What holds with mirror symmetry (issue 34): both pulled sides are remeshed alike, each
    to the detail size, and the shape stays symmetric to within a fraction of the edge length
    (each vertex's mirror image lies that near the surface); the triangulations of the two
    sides are not mirror images of each other (the remesh visits edges in index order)."""
    vertices, faces = icosphere(4)  # symmetric across x = 0
    median = median_edge_length(vertices, faces)
    sculptor = Sculptor(
        vertices, faces, settings=EngineSettings(material=CUBIC, dynamic_topology=True)
    )
    direction = np.array([0.6, 0.0, 0.8])
    row = int(np.argmax(vertices @ direction))
    center = vertices[row].copy()
    step = 0.02 * sculptor.model_size * direction
    sculptor.begin_stroke(Brush("grab", radius=0.08, symmetry="x"))
    for _ in range(12):
        sculptor.stroke_event(BrushEvent(center=center, delta=step))
        center = center + step
    sculptor.end_stroke()
    pulled, cells = sculptor.vertices, sculptor.faces
    assert len(pulled) > len(vertices)  # remeshed
    euler_and_check(pulled, cells)
    assert edge_lengths(pulled, cells).max() <= 2.0 * median
    mirrored = pulled * np.array([-1.0, 1.0, 1.0])
    gap = distance_to_surface(mirrored, pulled, cells)
    assert gap.max() <= 0.5 * median, gap.max() / median
    # both spikes are there and alike: as many vertices on each side of the plane, nearly
    right, left = np.sum(pulled[:, 0] > 0.05), np.sum(pulled[:, 0] < -0.05)
    assert abs(right - left) <= 0.05 * right
    # the tips reach equally far (a tip may be an edge: its highest vertex either end)
    reach, other = (pulled @ direction).max(), (pulled @ (direction * [-1.0, 1.0, 1.0])).max()
    assert abs(reach - other) <= 0.05 * median
    assert reach - (vertices @ direction).max() > 0.8 * 12 * 0.02 * sculptor.model_size


# -- Mesh → Remesh computed ahead (off the GUI thread) ------------------------------------------
def test_a_prepared_remesh_reports_progress_cancels_cleanly_and_refuses_a_changed_mesh():
    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces)
    size = 1.5 * median_edge_length(vertices, faces) / sculptor.model_size
    prepared = sculptor.remesher.prepare(size)
    assert np.array_equal(sculptor.faces, faces)  # preparing changes nothing

    def cancel(fraction: float) -> None:
        raise KeyboardInterrupt  # what a cancelled background task raises

    with pytest.raises(KeyboardInterrupt):
        prepared.compute(cancel)
    with pytest.raises(ValueError, match="not computed"):
        sculptor.remesher.remesh(size, prepared=prepared)
    fractions: list[float] = []
    prepared.compute(fractions.append)
    assert fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] < 1
    assert len(fractions) > 1
    assert np.array_equal(sculptor.faces, faces)  # computing on its copy changes nothing
    direct = Sculptor(vertices, faces)
    direct.remesher.remesh(size)
    sculptor.remesher.remesh(size, prepared=prepared)
    assert np.array_equal(sculptor.faces, direct.faces)
    assert np.array_equal(sculptor.vertices, direct.vertices)
    assert sculptor.history.undo_labels[-1] == "remesh"
    sculptor.undo()
    assert np.array_equal(sculptor.faces, faces) and np.array_equal(sculptor.vertices, vertices)
    # the mesh changed since it was prepared: refused, nothing changed
    stale = sculptor.remesher.prepare(size).compute()
    sculptor.begin_stroke(Brush("grab", radius=0.1))
    sculptor.stroke_event(BrushEvent(center=vertices[0], delta=np.array([0.0, 0.0, 0.05])))
    sculptor.end_stroke()
    moved = sculptor.vertices.copy()
    with pytest.raises(ValueError, match="changed since"):
        sculptor.remesher.remesh(size, prepared=stale)
    assert np.array_equal(sculptor.vertices, moved) and np.array_equal(sculptor.faces, faces)


# -- per-event cost: the region's, not the mesh's -------------------------------------------------
def test_each_event_measures_strain_only_on_the_faces_it_moved(monkeypatch):
    """Dynamic topology reads the faces around the rows an event moved, not every face, and
    takes the remeshed arrays without copying them again."""
    vertices, faces = icosphere(5)
    sculptor = Sculptor(
        vertices, faces, settings=EngineSettings(material=CUBIC, dynamic_topology=True)
    )
    measured: list[int] = []
    strained = stroke_module.strained_corners

    def spy(reference, points, cells, marked, tolerance):
        measured.append(int(np.count_nonzero(marked[cells].any(axis=1))))
        return strained(reference, points, cells, marked, tolerance)

    monkeypatch.setattr(stroke_module, "strained_corners", spy)
    adopted = []
    state = sculptor._mesh
    adopt = state.adopt
    monkeypatch.setattr(
        state, "adopt", lambda mesh, owned=False: adopted.append(mesh) or adopt(mesh, owned)
    )
    center = vertices[int(np.argmax(vertices[:, 2]))].copy()
    step = np.array([0.0, 0.0, 0.01 * sculptor.model_size])
    sculptor.begin_stroke(Brush("grab", radius=0.03, influence=2.0))
    for _ in range(6):
        sculptor.stroke_event(BrushEvent(center=center, delta=step))
        center = center + step
    sculptor.end_stroke()
    assert measured and max(measured) < 0.1 * len(faces)
    assert adopted and state.vertices is adopted[-1].vertices  # no copy
    assert state.faces is adopted[-1].faces


@pytest.mark.parametrize(
    ("length", "region", "words"),
    [
        (0.0, None, "target_length must be a positive length"),
        (float("nan"), None, "target_length must be a positive length"),
        (np.ones(3), None, "target_length must be one length or"),
        (0.1, np.ones(3, dtype=bool), "region must have shape"),
    ],
)
def test_remesh_names_a_bad_length_or_region(length, region, words) -> None:
    vertices, faces = icosphere(2)
    region = np.ones(len(vertices), dtype=bool) if region is None else region
    with pytest.raises(ValueError, match=words):
        remesh(vertices, faces, region, length)


def test_a_pause_in_a_stroke_does_not_remesh_its_whole_path(monkeypatch) -> None:
    """A tiny move after a drag (the pointer paused): the brush's core is measured against the
    fastest the stroke went, so the region remeshed stays the size of a moving event's (at 1M
    vertices the whole path took 20 s)."""
    regions: list[int] = []
    remesh_now = stroke_module.remesh

    def counted(vertices, faces, region, *args, **kwargs):
        regions.append(int(np.count_nonzero(region)))
        return remesh_now(vertices, faces, region, *args, **kwargs)

    monkeypatch.setattr(stroke_module, "remesh", counted)
    vertices, faces = default_model()
    sculptor = Sculptor(vertices, faces, settings=EngineSettings(dynamic_topology=True))
    center = vertices[int(np.argmax(vertices[:, 1]))].copy()
    step = 0.004 * sculptor.model_size * np.array([1.0, 0.3, 0.0])
    sculptor.begin_stroke(Brush("grab", radius=0.03))
    for k in range(10):
        sculptor.stroke_event(BrushEvent(center + k * step, step))
    moving = regions[-1]
    sculptor.stroke_event(BrushEvent(center + 10 * step, 1e-3 * step))
    sculptor.end_stroke()
    assert regions[-1] <= moving, (regions[-1], moving)


# -- texture coordinates through a stroke ---------------------------------------------------------
def textured_pull(sculptor: Sculptor, events: int = 8) -> None:
    """A grab near the sphere's seam (x = 0), its reach bounded (most vertices stay)."""
    direction = np.array([0.1, 0.3, 1.0]) / np.linalg.norm([0.1, 0.3, 1.0])
    center = sculptor.vertices[int(np.argmax(sculptor.vertices @ direction))].copy()
    step = 0.02 * sculptor.model_size * direction
    sculptor.begin_stroke(Brush("grab", radius=0.04, influence=2.0))
    for _ in range(events):
        sculptor.stroke_event(BrushEvent(center=center, delta=step))
        center = center + step
    sculptor.end_stroke()


def textured_icosphere(level: int = 5) -> tuple[np.ndarray, ...]:
    """An icosphere with :func:`textured_sphere`'s two charts (each row used once) and mask."""
    vertices, faces = icosphere(level)
    east = vertices[faces].mean(axis=1)[:, 0] > 0
    rows, corners = np.unique(
        np.where(east[:, None], faces, faces + len(vertices)), return_inverse=True
    )
    uv = np.concatenate([vertices[:, 1:], vertices[:, 1:] + [10.0, 0.0]])[rows]
    uv_faces = corners.reshape(-1, 3)
    uv_faces[-3:] = -1  # a few faces without texture
    return vertices, faces, uv, uv_faces, 0.2 + 0.1 * vertices[:, 0]


def arrays(sculptor: Sculptor) -> tuple[np.ndarray, ...]:
    mesh = sculptor.mesh
    assert mesh.uv is not None and mesh.uv_faces is not None
    return mesh.vertices, mesh.faces, mesh.uv, mesh.uv_faces.astype(np.int64), mesh.mask


def test_a_textured_stroke_undoes_and_redoes_bit_for_bit_from_a_step_of_what_changed():
    """A textured mesh's dynamic-topology stroke keeps its texture corners (each face on one
    chart, the seam a seam, the rows the faces use and no others of the region) and its undo
    step holds what changed (whole snapshots of the meshes before and after: 30x more), which
    gives back vertices, faces, uv, uv_faces and the mask bit for bit, and again on redo."""
    vertices, faces, uv, uv_faces, mask = textured_icosphere()
    sculptor = Sculptor(
        vertices, faces, uv=uv, uv_faces=uv_faces, settings=EngineSettings(dynamic_topology=True)
    )
    sculptor._mesh.set_mask_rows(MaskRows(np.arange(len(vertices)), mask))
    start = tuple(a.copy() for a in arrays(sculptor))
    textured_pull(sculptor)
    after = tuple(a.copy() for a in arrays(sculptor))
    new_v, new_f, new_uv, new_corners, new_mask = after
    assert len(new_f) != len(faces)  # remeshed
    euler_and_check(new_v, new_f)
    textured = new_corners[:, 0] >= 0
    assert np.count_nonzero(~textured) == 3 and np.all(new_corners[~textured] == -1)
    chart = new_uv[new_corners[textured]][:, :, 0] > 5.0
    assert np.all(chart == chart[:, :1])  # one chart per face
    assert np.array_equal(np.unique(new_corners[textured]), np.arange(len(new_uv)))
    assert np.all((new_mask > 0.1 - 1e-12) & (new_mask < 0.3 + 1e-12))  # interpolated
    whole = sum(a.nbytes for a in start + after) - (start[1].nbytes + after[1].nbytes) // 2
    whole -= (start[3].nbytes + after[3].nbytes) // 2  # the faces int32 in a snapshot
    assert sculptor.history.memory_bytes < 0.1 * whole
    for _ in range(2):
        sculptor.undo()
        assert all(np.array_equal(a, b) for a, b in zip(arrays(sculptor), start, strict=True))
        state = sculptor._mesh  # the engine's arrays (a snapshot's faces are int32)
        assert state.faces.dtype == np.int64 and state.uv_faces.dtype == np.int64
        sculptor.redo()
        assert all(np.array_equal(a, b) for a, b in zip(arrays(sculptor), after, strict=True))


def test_a_textured_session_replays_bit_for_bit():
    vertices, faces, uv, uv_faces, _ = textured_icosphere(4)
    settings = EngineSettings(material=CUBIC, dynamic_topology=True)
    sculptor = Sculptor(vertices, faces, uv=uv, uv_faces=uv_faces, settings=settings)
    textured_pull(sculptor, 5)
    textured_pull(sculptor, 4)
    sculptor.undo()
    sculptor.redo()
    after = arrays(sculptor)
    session = json.loads(json.dumps(sculptor.session()))
    again = Sculptor.from_session(session, vertices, faces, uv, uv_faces)
    again.replay(session["operations"])
    assert all(np.array_equal(a, b) for a, b in zip(arrays(again), after, strict=True))
    again.undo()
    again.undo()
    start = (vertices, faces, uv, uv_faces, np.zeros(len(vertices)))
    assert all(np.array_equal(a, b) for a, b in zip(arrays(again), start, strict=True))


def test_the_remesh_reads_and_compacts_only_the_regions_texture_rows(monkeypatch):
    """The patch holds the texture rows its faces use, not the whole array; rows outside the
    region stay as they were, in order, an unused one included (a whole-mesh compaction
    dropped it), and new rows come after them."""
    vertices, faces, uv, uv_faces, _ = textured_icosphere(4)
    uv = np.concatenate([uv, [[7.0, 7.0]]])  # a row no face uses
    sizes: list[int] = []
    patch = remesh_module._Patch

    def spy(*args):
        sizes.append(len(args[6]))
        return patch(*args)

    monkeypatch.setattr(remesh_module, "_Patch", spy)
    region = vertices[:, 2] > 0.9
    target = 0.5 * median_edge_length(vertices, faces)
    done = remesh(vertices, faces, region, target, uv=uv, uv_faces=uv_faces)
    assert len(done.faces) > len(faces) and sizes[0] < 0.1 * len(uv)
    assert done.uv_kept is not None and done.uv is not None and done.uv_faces is not None
    kept = np.flatnonzero(done.uv_kept >= 0)
    assert np.array_equal(done.uv_kept[kept], np.arange(len(kept)))  # in order, first
    assert done.uv_kept[-1] >= 0 and np.array_equal(done.uv[done.uv_kept[-1]], [7.0, 7.0])
    outside = done.kept_faces & (uv_faces[:, 0] >= 0)
    carried = done.uv_faces[: np.count_nonzero(done.kept_faces)][outside[done.kept_faces]]
    assert np.array_equal(done.uv[carried], uv[uv_faces[outside]])
    # the region's rows no face uses any more are dropped (collapses), no others
    used = np.zeros(len(done.uv), dtype=bool)
    used[done.uv_faces[done.uv_faces >= 0]] = True
    assert np.array_equal(np.flatnonzero(~used), [done.uv_kept[-1]])


def test_a_texture_row_shared_with_far_corners_is_kept():
    """Texture rows shared by corners far apart (deduplicated UVs): a row the region's faces no
    longer use but a face outside it does stays, and every corner names a row."""
    vertices, faces, _, _, _ = textured_icosphere(3)
    uv, uv_faces = vertices[:, :2].copy(), faces.copy()
    region = vertices[:, 2] > 0.5
    south = np.flatnonzero(np.all(vertices[faces][:, :, 2] < -0.5, axis=1))
    north = np.flatnonzero(region)
    uv_faces[south[: len(north) // 3]] = north[: 3 * (len(north) // 3)].reshape(-1, 3)
    done = remesh(
        vertices, faces, region, 1.7 * median_edge_length(vertices, faces), uv=uv, uv_faces=uv_faces
    )
    assert len(done.vertices) < len(vertices)  # collapses
    assert done.uv is not None and done.uv_faces is not None
    assert done.uv_faces.min() >= 0 and done.uv_faces.max() < len(done.uv)
    carried = done.uv_faces[: np.count_nonzero(done.kept_faces)]
    assert np.array_equal(carried, done.uv_kept[uv_faces[done.kept_faces]])


def test_a_free_vertex_whose_normals_cancel_stays_put_in_the_relaxation():
    """A fold's vertex whose faces' normals sum to exactly zero has no tangent plane: the
    relaxation leaves it where it is (it ended the stroke with a shape mismatch, or NaN) and
    still moves the others."""
    fold = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0.5, 0], [0, -1, 0]]  # normals +z -z -z +z
    angles = np.arange(6) * np.pi / 3
    fan = np.column_stack([5 + np.cos(angles), np.sin(angles), np.zeros(6)])
    points = np.concatenate([fold, [[5.2, 0.1, 0.0]], fan])
    faces = np.array(
        [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]]
        + [[5, 6 + k, 6 + (k + 1) % 6] for k in range(6)]
    )
    n = len(points)
    closed = np.isin(np.arange(n), [0, 5])
    patch = remesh_module._Patch(
        points.copy(),
        faces,
        closed,
        np.zeros(n, bool),
        np.zeros(n),
        np.ones(n),
        None,
        np.full((len(faces), 3), -1),
    )
    patch.relax(1e-12)
    assert np.array_equal(patch.points[0], [0, 0, 0])
    assert not np.array_equal(patch.points[5], points[5]) and np.isfinite(patch.points).all()
