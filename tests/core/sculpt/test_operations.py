"""Typed operation records, the session schema, and settings changes as undo steps."""

import json

import numpy as np
import pytest
import trimesh

from gogreen_core import Material
from gogreen_core.files.presets import builtin_presets
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, SplineRadial
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.operations import (
    OPERATIONS,
    SETTINGS_CHANGES,
    ConstraintAdd,
    ConstraintDrag,
    ConstraintRemove,
    ConstraintsClear,
    MaskClear,
    MaskInvert,
    Redo,
    Remesh,
    Stroke,
    Subdivide,
    Undo,
    operation_from_dict,
)
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import SESSION_VERSION, parse_session
from gogreen_core.validation import ParameterError

CUBIC = Material.cubic(3.0, 1.5, 0.4)


def change(group, continued=False, **values):
    """The change record of settings ``group`` (its other fields at their defaults)."""
    record = SETTINGS_CHANGES[group]
    full = {s.name: values.get(s.name, s.initial()) for s in record.group_rows()}
    return record(full, continued)


@pytest.fixture(scope="module")
def sphere():
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    return np.array(mesh.vertices), np.array(mesh.faces)


def records():
    spline = SplineRadial.from_profile(GaussianRadial(1.0), 4)
    return [
        Stroke(
            Brush("pinch", radius=0.2, symmetry="x"),
            (BrushEvent([0, 0, 1], amount=0.1, axis=[0, 1, 1], direction=[1, 0, 0]),),
        ),
        Stroke(Brush("grab", influence=np.inf), (BrushEvent([0, 0, 1], [0, 0.1, 0]),)),
        Stroke(
            Brush("grab_biscale"),
            (
                BrushEvent([0, 0, 1], [0, 0.1, 0]),
                BrushEvent([0, 0.1, 1], [0, 0.1, 0], radius_factor=0.3),
            ),
        ),
        change("material", material=CUBIC),
        change("material", True, material=Material.isotropic(2.0, 0.2)),
        change("falloff", falloff=spline, l_max=4, brush_weights={"pinch": tuple(np.arange(6.0))}),
        change("falloff", True, falloff=KelvinletRadial(1.0), l_max=6),
        change("constraint_radius", True, constraint_radius=0.2),
        ConstraintAdd(np.array([0.0, 0.0, 1.0])),
        ConstraintDrag(0, np.array([0.0, 0.05, 0.0]), continued=True),
        ConstraintRemove(0),
        ConstraintsClear(),
        Stroke(Brush("mask", radius=0.2), (BrushEvent([0, 0, 1], [0, 0.1, 0], amount=-0.5),)),
        MaskInvert(),
        MaskClear(),
        Subdivide(),
        Subdivide(unmasked_only=True),
        change("dynamic_topology", dynamic_topology=True),
        change("dynamic_topology", True, dynamic_topology=True, detail_size=0.01),
        Remesh(0.02),
        Remesh(None),
        Remesh(0.005, unmasked_only=True, iterations=2),
        Undo(),
        Redo(),
    ]


def test_every_operation_round_trips_through_json():
    seen = set()
    for record in records():
        data = json.loads(json.dumps(record.to_dict()))
        again = operation_from_dict(data, "op")
        assert type(again) is type(record)
        assert again.to_dict() == record.to_dict()
        seen.add(record.name)
    assert seen == set(OPERATIONS)


@pytest.mark.parametrize(
    ("data", "parameter"),
    [
        ({"op": "smudge"}, "operations[2].op"),
        ({}, "operations[2].op"),
        ([1, 2], "operations[2]"),
        ({"op": "stroke", "brush": {}, "events": 7}, "operations[2].events"),
        ({"op": "stroke", "brush": {}, "events": [3]}, "operations[2].events[0]"),
        (
            {"op": "stroke", "brush": {}, "events": [{"center": [0, 0, 0], "delta": [0, "x", 0]}]},
            "operations[2].events[0].delta",
        ),
        ({"op": "stroke", "brush": {"radius": "big"}, "events": []}, "operations[2].brush.radius"),
        ({"op": "stroke", "brush": {"hue": 1}, "events": []}, "operations[2].brush.hue"),
        ({"op": "material", "material": {"voigt": 3}}, "operations[2].material.voigt"),
        ({"op": "falloff", "falloff": {"type": "gaussian", "eps": 1}}, "operations[2].l_max"),
        (
            {"op": "falloff", "falloff": {"type": "gaussian", "eps": -1}, "l_max": 4},
            "operations[2].falloff.eps",
        ),
        (
            {"op": "falloff", "falloff": {"type": "gaussian", "eps": 1}, "l_max": 4.5},
            "operations[2].l_max",
        ),
        (
            {
                "op": "falloff",
                "falloff": {"type": "gaussian", "eps": 1},
                "l_max": 4,
                "brush_weights": {"grab": [1, 2]},
            },
            "operations[2].brush_weights.grab",
        ),
        ({"op": "undo", "continued": True}, "operations[2].continued"),
        (
            {"op": "material", "material": CUBIC.to_dict(), "continued": 1},
            "operations[2].continued",
        ),
        ({"op": "constraint_drag", "index": 0.5, "delta": [0, 0, 0]}, "operations[2].index"),
        ({"op": "constraint_remove", "index": -1}, "operations[2].index"),
        ({"op": "constraint_add", "point": [0, 0]}, "operations[2].point"),
        ({"op": "subdivide", "unmasked_only": "yes"}, "operations[2].unmasked_only"),
        ({"op": "mask_invert", "rows": [1]}, "operations[2].rows"),
        ({"op": "constraint_radius", "radius": None}, "operations[2].radius"),
        ({"op": "undo", "extra": 1}, "operations[2].extra"),
    ],
)
def test_operation_schema_names_the_field(data, parameter):
    with pytest.raises(ParameterError) as info:
        operation_from_dict(data, "operations[2]")
    assert info.value.parameter == parameter
    assert parameter in str(info.value)


def session_of(sculptor: Sculptor) -> dict:
    return json.loads(json.dumps(sculptor.session()))


def test_settings_changes_are_undo_steps_restored_exactly(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    first = sculptor.settings
    spline = SplineRadial.from_profile(KelvinletRadial(1.0), 6)
    sculptor.change_settings(material=CUBIC)
    sculptor.change_settings(falloff=spline, l_max=6, brush_weights={"pinch": np.linspace(1, 2, 8)})
    sculptor.change_settings(constraint_radius=0.25)
    assert sculptor.history.undo_labels == ["material", "falloff", "constraint radius"]
    after = sculptor.settings
    assert sculptor.undo() == "constraint radius"
    assert sculptor.settings.constraint_radius == 0.1
    assert sculptor.undo() == "falloff"
    assert sculptor.settings.falloff.to_dict() == first.falloff.to_dict()
    assert sculptor.settings.l_max == 8 and not sculptor.settings.brush_weights
    assert sculptor.undo() == "material"
    assert sculptor.settings.material == first.material
    for _ in range(3):
        sculptor.redo()
    assert sculptor.settings == after
    assert sculptor.settings.falloff.to_dict() == spline.with_eps(1.0).to_dict()
    # the engine computes with the restored settings: the same stroke as a fresh sculptor's
    brush, event = Brush("twist", radius=0.3), BrushEvent(vertices[0], amount=0.2)
    sculptor.undo()
    sculptor.undo()
    sculptor.apply_brush(brush, [event])
    fresh = Sculptor(vertices, faces, material=CUBIC)
    fresh.apply_brush(brush, [event])
    assert np.array_equal(sculptor.vertices, fresh.vertices)


def test_a_slider_drag_is_one_step_and_replays(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[1], [0.0, 0.02, 0.0])])
    for k, poisson in enumerate(np.linspace(0.1, 0.45, 6)):
        sculptor.change_settings(material=Material.isotropic(1.0, poisson), continued=k > 0)
    for k, radius in enumerate((0.12, 0.15, 0.2)):
        sculptor.change_settings(constraint_radius=radius, continued=k > 0)
    assert sculptor.history.undo_labels == ["Wide grab stroke", "material", "constraint radius"]
    ops = sculptor.session()["operations"]
    assert [op["op"] for op in ops] == ["stroke", "material", "constraint_radius"]
    assert ops[1]["material"] == Material.isotropic(1.0, 0.45).to_dict()
    sculptor.apply_brush(Brush("scale"), [BrushEvent(vertices[2], amount=0.1)])
    sculptor.undo()
    sculptor.undo()  # the radius drag
    sculptor.undo()  # the whole material drag at once
    assert sculptor.settings.material == Material.isotropic(1.0, 0.3)
    # a continued change after an undo starts a new step: it never joins an undone one
    sculptor.change_settings(material=CUBIC, continued=True)
    sculptor.change_settings(
        falloff=KelvinletRadial(1.0), continued=True
    )  # joins the material's step
    assert sculptor.history.undo_labels == ["Wide grab stroke", "material"]
    session = session_of(sculptor)
    assert session["version"] == SESSION_VERSION == 7
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert again.settings == sculptor.settings
    assert again.history.undo_labels == sculptor.history.undo_labels
    assert again.session()["operations"] == session["operations"]
    again.undo()
    assert again.settings.material == Material.isotropic(1.0, 0.3)
    assert isinstance(again.settings.falloff, GaussianRadial)


def test_a_preset_is_one_undo_step(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    wood = next(p for p in builtin_presets() if "Wood" in p.name)
    wood.apply(sculptor)
    assert sculptor.history.undo_labels == ["material"]
    assert sculptor.settings.material == wood.material and sculptor.settings.l_max == wood.l_max
    sculptor.undo()
    assert (
        sculptor.settings.material == Material.isotropic(1.0, 0.3) and sculptor.settings.l_max == 8
    )


def test_a_version_1_undo_that_means_another_step_today_is_refused(sphere):
    vertices, faces = sphere
    # written before settings were undo steps: this undo undid the stroke, not the material
    session = {
        "format": "gogreen-session",
        "version": 1,
        "mesh": {"vertices": len(vertices), "faces": len(faces)},
        "settings": {
            "material": Material.isotropic(1.0, 0.3).to_dict(),
            "falloff": GaussianRadial(1.0).to_dict(),
            "l_max": 8,
            "degree_weights": None,
        },
        "operations": [
            Stroke(Brush("grab"), (BrushEvent(vertices[1], [0.0, 0.02, 0.0]),)).to_dict(),
            {"op": "material", "material": CUBIC.to_dict()},
            {"op": "undo"},
        ],
    }
    with pytest.raises(ParameterError, match=r"operations\[2\] \(undo\)") as info:
        Sculptor.from_session(session, vertices, faces)
    assert info.value.parameter == "operations[2]"


def test_parse_session_checks_everything_before_applying(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[1], [0.0, 0.02, 0.0])])
    session = session_of(sculptor)
    parsed = parse_session(session)
    assert [op.name for op in parsed.operations] == ["stroke"] and parsed.operations[0].steps == 1
    session["operations"].append({"op": "constraint_drag", "index": 0.5, "delta": [0, 0, 0]})
    target = Sculptor(vertices, faces)
    with pytest.raises(ParameterError, match=r"operations\[1\]\.index"):
        target.replay(session["operations"])
    assert np.array_equal(target.vertices, vertices)  # the good first stroke was not applied
    assert target.session()["operations"] == []


def test_a_replay_failing_part_way_is_rolled_back(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[1], [0.0, 0.02, 0.0])])
    before = sculptor.vertices.copy()
    labels = sculptor.history.undo_labels
    operations = [
        Stroke(Brush("grab"), (BrushEvent(vertices[3], [0.0, 0.0, 0.02]),)).to_dict(),
        {"op": "material", "material": CUBIC.to_dict()},
        {"op": "constraint_add", "point": [0.0, 0.0, 1.0]},
        {"op": "constraint_remove", "index": 3},  # there is one pin: refused when applied
    ]
    with pytest.raises(ParameterError, match=r"operations\[3\]\.index") as info:
        sculptor.replay(operations)
    assert info.value.parameter == "operations[3].index"
    assert np.array_equal(sculptor.vertices, before)
    assert sculptor.history.undo_labels == labels
    assert sculptor.settings.material == Material.isotropic(1.0, 0.3)
    assert len(sculptor.constraint_points) == 0
    assert [op["op"] for op in sculptor.session()["operations"]] == ["stroke"]


def test_an_unchanged_value_is_no_step_but_a_drag_back_to_the_start_is_one(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    sculptor.change_settings(material=Material.isotropic(1.0, 0.3))  # the current one
    sculptor.change_settings(constraint_radius=0.1)
    assert not sculptor.history.can_undo and sculptor.session()["operations"] == []
    sculptor.change_settings(material=CUBIC)
    sculptor.change_settings(material=Material.isotropic(1.0, 0.3), continued=True)  # dragged back
    assert sculptor.history.undo_labels == ["material"]
    session = session_of(sculptor)
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert again.history.undo_labels == ["material"]
    assert again.session()["operations"] == session["operations"]


def test_settings_refused_inside_a_stroke_and_bad_values_change_nothing(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    with pytest.raises(ParameterError, match="radius") as info:
        sculptor.change_settings(constraint_radius=0.0)
    assert info.value.parameter == "constraint_radius"
    with pytest.raises(ParameterError) as info:
        sculptor.change_settings(
            falloff=GaussianRadial(1.0), l_max=4, brush_weights={"grab": [1.0, 2.0]}
        )
    assert info.value.parameter == "brush_weights.grab"
    with pytest.raises(ParameterError) as info:
        sculptor.change_settings(material="steel")
    assert info.value.parameter == "material"
    sculptor.begin_stroke(Brush())
    with pytest.raises(RuntimeError, match="during a stroke"):
        sculptor.change_settings(material=CUBIC)
    sculptor.cancel_stroke()
    assert not sculptor.history.can_undo and sculptor.session()["operations"] == []
    assert (
        sculptor.settings.material == Material.isotropic(1.0, 0.3) and sculptor.settings.l_max == 8
    )


def test_per_event_radius_factors_replay_bit_identically(sphere):
    """Pen pressure → radius: each event's radius factor is recorded, and the session replays
    bit for bit; events at factor 1 are written as before (no field)."""
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, material=CUBIC)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    factors = [1.0, 0.8, 0.55, 0.3]
    for brush in (Brush("grab"), Brush("grab_triscale", symmetry="x"), Brush("wrinkle")):
        events = [
            BrushEvent(top + np.array([0, 0.02 * k, 0]), [0, 0.02, 0.01], radius_factor=f)
            for k, f in enumerate(factors)
        ]
        sculptor.apply_brush(brush, events)
    twist = [BrushEvent(top, amount=0.1, axis=[0, 0, 1], radius_factor=f) for f in factors]
    sculptor.apply_brush(Brush("twist", radius=0.2), twist)
    scale = [BrushEvent(top, amount=0.05, radius_factor=1e-9)]  # clamped to MIN_RADIUS
    sculptor.apply_brush(Brush("scale", radius=0.2), scale)
    session = session_of(sculptor)
    events = session["operations"][0]["events"]
    assert "radius_factor" not in events[0]
    assert [e["radius_factor"] for e in events[1:]] == factors[1:]
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert session_of(again) == session
    # the factor matters: the same strokes at full radius end elsewhere
    full = json.loads(json.dumps(session).replace('"radius_factor"', '"_rf"'))
    for op in full["operations"]:
        for event in op.get("events", []):
            event.pop("_rf", None)
    other = Sculptor.from_session(full, vertices, faces)
    other.replay(full["operations"])
    assert not np.allclose(other.vertices, sculptor.vertices)


def test_an_event_radius_factor_shrinks_the_moved_region(sphere):
    vertices, faces = sphere
    top = vertices[int(np.argmax(vertices[:, 2]))]
    reach = {}
    for factor in (1.0, 0.3):
        sculptor = Sculptor(vertices, faces)
        brush = Brush("grab", radius=0.1, influence=4.0)  # a ball that fits on the sphere
        moved = sculptor.apply_brush(brush, [BrushEvent(top, [0, 0, 0.02], radius_factor=factor)])
        reach[factor] = np.linalg.norm(vertices[moved] - top, axis=1).max()
        outer = brush.influence * max(brush.radius * factor, 1e-6) * sculptor.model_size
        assert reach[factor] <= outer + 0.02
    assert reach[0.3] < 0.4 * reach[1.0]
