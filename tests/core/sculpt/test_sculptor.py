"""Sculpting engine: brushes, streamlines, symmetry, constraints, history and session replay."""

import itertools
import json

import numpy as np
import pytest
import trimesh

from gogreen_core import Material
from gogreen_core.physics.radial import KelvinletRadial
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.sculptor import Sculptor

ANISOTROPIC = Material.cubic(3.0, 1.5, 0.4).rotated(
    np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
)


def sphere(subdivisions: int = 4):
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    return np.array(mesh.vertices), np.array(mesh.faces)


def volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


@pytest.fixture(scope="module", params=["made", "stanford-bunny.obj"])
def bunny(request, made_open_tiny, shared_mesh):
    """The shared bunny (skipped when absent) or its stand-in: open and tiny (conftest.py)."""
    if request.param == "made":
        return made_open_tiny.vertices, made_open_tiny.faces
    mesh = trimesh.load(shared_mesh(request.param), process=False)
    return np.array(mesh.vertices), np.array(mesh.faces)


@pytest.mark.parametrize("kind", ["grab", "grab_biscale", "grab_triscale"])
def test_grab_moves_the_picked_vertex_by_exactly_delta(bunny, kind):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    picked = 1234
    center = vertices[picked].copy()
    delta = 0.01 * sculptor.model_size * np.array([0.3, 1.0, -0.5])
    sculptor.apply_brush(Brush(kind, radius=0.08), [BrushEvent(center, delta)])
    moved = sculptor.vertices[picked] - center
    assert np.abs(moved - delta).max() < 1e-12 * sculptor.model_size


def test_grab_stroke_of_many_events_follows_the_cursor(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    path = (
        vertices[77]
        + 0.02
        * sculptor.model_size
        * np.array([[np.cos(t), np.sin(t), t] for t in np.linspace(0, 1.5, 8)])
        - 0.02 * sculptor.model_size * np.array([1.0, 0.0, 0.0])
    )
    path[0] = vertices[77]
    events = [BrushEvent(a, b - a) for a, b in itertools.pairwise(path)]
    sculptor.apply_brush(Brush("grab", radius=0.1), events)
    assert np.abs(sculptor.vertices[77] - path[-1]).max() < 1e-12 * sculptor.model_size


def test_incompressible_material_keeps_volume_and_compressible_scale_changes_it():
    vertices, faces = sphere(4)
    v0 = volume(vertices, faces)
    whole = dict(radius=0.15, influence=np.inf, substeps=8)
    rubber = Sculptor(vertices, faces, material=Material.isotropic(1.0, 0.499))
    top = vertices[np.argmax(vertices[:, 2])]
    rubber.apply_brush(Brush("grab", **whole), [BrushEvent(top, [0.1, 0.05, 0.25])])
    rubber.apply_brush(Brush("twist", **whole), [BrushEvent(top, amount=0.6, axis=[0.2, 0.1, 1.0])])
    assert abs(volume(rubber.vertices, faces) / v0 - 1) < 1e-3
    assert np.abs(rubber.vertices - vertices).max() > 0.05  # it did deform

    soft = Sculptor(vertices, faces, material=Material.isotropic(1.0, 0.2))
    soft.apply_brush(Brush("scale", **whole), [BrushEvent(top, amount=0.3)])
    assert volume(soft.vertices, faces) / v0 - 1 > 0.01


def test_far_vertices_do_not_move_under_a_local_falloff(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    brush = Brush("grab", radius=0.05, influence=3.0)
    center = vertices[500]
    delta = 0.02 * sculptor.model_size * np.array([0.0, 1.0, 0.0])
    moved = sculptor.apply_brush(brush, [BrushEvent(center, delta)])
    outer = brush.cutoff(sculptor.model_size)[1]
    far = np.linalg.norm(vertices - center, axis=1) > outer + np.linalg.norm(delta)
    assert far.sum() > len(vertices) // 2
    assert np.array_equal(sculptor.vertices[far], vertices[far])
    assert not np.intersect1d(np.flatnonzero(far), moved).size
    # the cutoff is smooth: the displacement fades continuously to 0 at its edge
    disp = np.linalg.norm(sculptor.vertices - vertices, axis=1)
    dist = np.linalg.norm(vertices - center, axis=1)
    near_edge = (dist > 0.95 * outer) & (dist < outer)
    inside = dist < 0.4 * outer
    assert disp[near_edge].max() < 0.06 * disp[inside].min()


def mirror_pairs(vertices: np.ndarray, axis: int) -> np.ndarray:
    mirrored = vertices.copy()
    mirrored[:, axis] *= -1
    keys = {tuple(np.round(v, 12)): i for i, v in enumerate(vertices)}
    return np.array([keys[tuple(np.round(v, 12))] for v in mirrored])


@pytest.mark.parametrize("kind", ["grab", "scale", "pinch"])
def test_mirror_symmetry_is_kept(kind):
    vertices, faces = sphere(4)
    pairs = mirror_pairs(vertices, 0)
    flip = np.array([-1.0, 1.0, 1.0])
    assert np.abs(vertices[pairs] * flip - vertices).max() == 0
    sculptor = Sculptor(vertices, faces, material=Material.isotropic(1.0, 0.3))
    brush = Brush(kind, radius=0.1, symmetry="x")
    start = vertices[np.argmax(vertices @ [0.3, 0.2, 1.0])]
    events = [
        BrushEvent(
            start + np.array([0.01 * k, 0, 0]),
            [0.02, 0.03, 0.05],
            amount=0.1,
            axis=[0.2, 0.3, 1.0],
            direction=[1.0, 0.0, 0.0],
        )
        for k in range(3)
    ]
    sculptor.apply_brush(brush, events)
    v = sculptor.vertices
    assert np.abs(v - vertices).max() > 1e-3
    assert np.abs(v[pairs] * flip - v).max() < 1e-12


def test_relative_radius_behaves_alike_at_any_model_size(bunny):
    vertices, faces = bunny
    results = []
    for scale in (1.0, 200.0):
        s = Sculptor(vertices * scale, faces, material=ANISOTROPIC)
        event = BrushEvent(vertices[900] * scale, scale * np.array([0.0, 0.01, 0.005]))
        s.apply_brush(Brush("grab", radius=0.1), [event])
        s.apply_brush(Brush("twist", radius=0.1), [BrushEvent(vertices[40] * scale, amount=0.3)])
        results.append(s.vertices / scale)
    assert np.abs(results[0] - results[1]).max() < 1e-9


def test_constraints_land_on_targets_and_low_rank_updates_match(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    sculptor.change_settings(constraint_radius=0.05)
    ids = [10, 800, 1600, 2400, 3000]
    for i in ids:
        sculptor.add_constraint(vertices[i])
    sculptor.remove_constraint(2)
    ids.pop(2)
    sculptor.add_constraint(vertices[1700])
    ids.append(1700)
    constraints = sculptor._pins.constraints
    full = np.linalg.inv(constraints.matrix)
    assert np.abs(constraints.inverse - full).max() < 1e-8 * np.abs(full).max()
    delta = 0.03 * sculptor.model_size * np.array([0.2, 1.0, 0.1])
    sculptor.drag_constraint(1, delta)
    moved = sculptor.vertices[ids] - vertices[ids]
    expected = np.zeros_like(moved)
    expected[1] = delta
    assert np.abs(moved - expected).max() < 1e-8 * sculptor.model_size
    assert np.allclose(sculptor.constraint_points[1], vertices[ids[1]] + delta)
    with pytest.raises(ValueError, match="coincides"):
        sculptor.add_constraint(vertices[ids[0]])


def test_undo_redo_restore_bit_for_bit(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[5], [0.0, 0.01, 0.0])])
    after_first = sculptor.vertices.copy()
    sculptor.apply_brush(Brush("pinch"), [BrushEvent(vertices[9], amount=0.2)])
    after_second = sculptor.vertices.copy()
    assert sculptor.undo() == "Pinch stroke"
    assert np.array_equal(sculptor.vertices, after_first)
    assert sculptor.undo() == "Wide grab stroke"
    assert np.array_equal(sculptor.vertices, vertices)
    assert sculptor.redo() == "Wide grab stroke"
    assert sculptor.redo() == "Pinch stroke"
    assert np.array_equal(sculptor.vertices, after_second)


def test_session_replay_reproduces_the_result_bit_for_bit(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces, falloff=KelvinletRadial(1.0), l_max=6)
    sculptor.change_settings(material=ANISOTROPIC)
    sculptor.apply_brush(
        Brush("grab_biscale", radius=0.07, symmetry="x"),
        [BrushEvent(vertices[3], [0.001, 0.002, 0.0]), BrushEvent(vertices[4], [0.0, 0.002, 0.0])],
    )
    sculptor.apply_brush(Brush("wrinkle"), [BrushEvent(vertices[30], [0.0, 0.0, 0.004])])
    sculptor.undo()
    sculptor.apply_brush(Brush("twist", strength=2), [BrushEvent(vertices[60], amount=0.1)])
    sculptor.add_constraint(vertices[100])
    sculptor.add_constraint(vertices[2000])
    sculptor.drag_constraint(0, [0.0, 0.003, 0.0])
    sculptor.drag_constraint(1, [0.002, 0.0, 0.0])
    sculptor.drag_constraint(1, [0.002, 0.001, 0.0], continued=True)
    assert sculptor.history.undo_labels[-2:] == ["constraint drag", "constraint drag"]
    sculptor.undo()  # the whole second drag
    sculptor.redo()
    text = json.dumps(sculptor.session())
    session = json.loads(text)
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: Brush("smudge"), "unknown brush"),
        (lambda: Brush(radius=0.0), "radius"),
        (lambda: Brush(radius=np.nan), "radius"),
        (lambda: Brush(substeps=-1), "substeps"),
        (lambda: Brush(symmetry="w"), "symmetry"),
        (lambda: BrushEvent([0, np.nan, 0]), "center"),
        (lambda: Sculptor(np.zeros((3, 3)), [[0, 1, 2]]), "zero size"),
        (lambda: Sculptor(np.eye(3), [[0, 1, 5]]), "faces reference"),
        (lambda: Sculptor([[0, 0, np.inf], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]), "NaN"),
    ],
)
def test_bad_input_raises_value_error(build, message):
    with pytest.raises(ValueError, match=message):
        build()


def test_a_failed_stroke_leaves_the_mesh_unchanged(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces)
    with pytest.raises(ValueError):
        sculptor.apply_brush(
            Brush("grab"), [BrushEvent(vertices[1], [0, 0.01, 0]), {"not": "an event"}]
        )
    assert np.array_equal(sculptor.vertices, vertices)
    assert not sculptor.in_stroke and not sculptor.history.can_undo


def test_a_continued_settings_drag_is_one_step_and_one_log_entry(bunny):
    vertices, faces = bunny
    sculptor = Sculptor(vertices, faces)
    # a slider or curve drag sets the material / falloff many times in a row
    sculptor.change_settings(falloff=KelvinletRadial(1.0), l_max=6)
    for k, poisson in enumerate((0.1, 0.2, 0.3)):
        sculptor.change_settings(material=Material.isotropic(1.0, poisson), continued=k > 0)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[3], [0.0, 0.002, 0.0])])
    sculptor.change_settings(material=Material.isotropic(1.0, 0.45))
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[9], [0.002, 0.0, 0.0])])
    ops = sculptor.session()["operations"]
    assert [op["op"] for op in ops] == ["falloff", "material", "stroke", "material", "stroke"]
    assert ops[1]["material"] == Material.isotropic(1.0, 0.3).to_dict()
    assert "continued" not in ops[1]  # the drag's first value started a step of its own
    assert sculptor.history.undo_labels == [
        "falloff",
        "material",
        "Wide grab stroke",
        "material",
        "Wide grab stroke",
    ]
    session = json.loads(json.dumps(sculptor.session()))
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert again.history.undo_labels == sculptor.history.undo_labels
