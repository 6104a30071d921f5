"""Hostile input (issue 15): broken sessions, presets, CLI arguments and extreme values get a
clear ValueError naming the field, and the mesh being edited survives unchanged."""

import copy
import json

import numpy as np
import pytest
import trimesh

from gogreen_core import Material, ParameterError
from gogreen_core.files.presets import Preset, load_preset
from gogreen_core.interaction.batch import main
from gogreen_core.mesh.mesh_io import MeshData, save_mesh
from gogreen_core.physics.radial import GaussianRadial, SplineRadial
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import SESSION_VERSION, load_session, parse_session

HUGE = 1e200
ANISOTROPIC = Material.cubic(3.0, 1.5, 0.4)


@pytest.fixture(scope="module")
def sphere():
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
    return np.array(mesh.vertices), np.array(mesh.faces)


@pytest.fixture(scope="module")
def recorded(sphere):
    """A valid session using every kind of operation, as JSON data."""
    vertices, faces = sphere
    s = Sculptor(vertices, faces)
    s.change_settings(material=ANISOTROPIC)
    s.change_settings(falloff=SplineRadial.from_profile(GaussianRadial(1.0), 4), l_max=4)
    s.apply_brush(Brush("grab"), [BrushEvent(vertices[0], [0.0, 0.05, 0.0], radius_factor=0.5)])
    s.apply_brush(Brush("twist"), [BrushEvent(vertices[5], amount=0.2, axis=[0, 1, 0])])
    s.change_settings(constraint_radius=0.2)
    s.add_constraint(vertices[10])
    s.add_constraint(vertices[20])
    s.drag_constraint(1, [0.0, 0.0, 0.05])
    s.undo()
    s.redo()
    s.remove_constraint(0)
    s.clear_constraints()
    return json.loads(json.dumps(s.session()))


def edited(session: dict, path: tuple, value) -> dict:
    """A deep copy of ``session`` with the item at ``path`` set to ``value``."""
    data = copy.deepcopy(session)
    target = data
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return data


def op_index(session: dict, name: str) -> int:
    return next(i for i, op in enumerate(session["operations"]) if op["op"] == name)


def hostile_sessions(session: dict):
    """(name, session data, expected parameter) for every field we can break."""
    stroke = op_index(session, "stroke")
    drag = op_index(session, "constraint_drag")
    add = op_index(session, "constraint_add")
    falloff = op_index(session, "falloff")
    ev = ("operations", stroke, "events", 0)
    br = ("operations", stroke, "brush")
    yield "mesh null", edited(session, ("mesh",), None), "mesh"
    yield "mesh vertices text", edited(session, ("mesh", "vertices"), "3"), "mesh.vertices"
    yield "settings list", edited(session, ("settings",), []), "settings"
    yield "format", edited(session, ("format",), "gogreen"), "format"
    yield "version text", edited(session, ("version",), "2"), "version"
    yield "version future", edited(session, ("version",), SESSION_VERSION + 1), "version"
    yield "operations object", edited(session, ("operations",), {}), "operations"
    for bad in (7, "stroke", None, [1]):
        yield f"operation {bad!r}", edited(session, ("operations", 0), bad), "operations[0]"
    yield "events 7", edited(session, (*ev[:3],), 7), f"operations[{stroke}].events"
    yield "event 7", edited(session, ev, 7), f"operations[{stroke}].events[0]"
    for field in ("center", "delta"):
        for bad in ("x", [0, 0], [0, None, 0], [0, float("nan"), 0], [0, 1e400, 0], None):
            name = f"operations[{stroke}].events[0].{field}"
            yield f"{field} {bad!r}", edited(session, (*ev, field), bad), name
    for bad in (float("nan"), float("inf"), 0, 0.0, -0.5, 1.5, 1e300, "0.5", None, True, [0.5]):
        name = f"operations[{stroke}].events[0].radius_factor"
        yield f"radius_factor {bad!r}", edited(session, (*ev, "radius_factor"), bad), name
    yield "amount text", edited(session, (*ev, "amount"), "1"), f"operations[{stroke}].events[0]."
    yield "event key", edited(session, (*ev, "speed"), 1), f"operations[{stroke}].events[0].speed"
    for field, bad in [
        ("substeps", 1e300),
        ("substeps", 0.5),
        ("substeps", True),
        ("radius", HUGE),
        ("radius", -1),
        ("strength", HUGE),
        ("strength", "1"),
        ("kind", 3),
        ("symmetry", 3),
        ("influence", -1),
        ("influence", "automatic"),
    ]:
        name = f"operations[{stroke}].brush.{field}"
        yield f"brush {field} {bad!r}", edited(session, (*br, field), bad), name
    for field, bad in [("index", 0.5), ("index", -1), ("index", "0"), ("delta", [0, 0, HUGE])]:
        name = f"operations[{drag}].{field}"
        yield f"drag {field} {bad!r}", edited(session, ("operations", drag, field), bad), name
    yield (
        "drag continued",
        edited(session, ("operations", drag, "continued"), "yes"),
        f"operations[{drag}].continued",
    )
    yield (
        "pin far",
        edited(session, ("operations", add, "point"), [1e300, 0, 0]),
        f"operations[{add}].point",
    )
    weights = ("operations", falloff, "brush_weights")
    for what, bad, where in [
        ("kind", {"bogus": [1.0] * 10}, "bogus"),
        ("length", {"pinch": [1.0, 2.0]}, "pinch"),
        ("nan", {"grab": [float("nan")] * 10}, "grab"),
        ("huge", {"grab": [1e300] * 10}, "grab"),
        ("type", ["grab"], None),
    ]:
        name = f"operations[{falloff}].brush_weights" + (f".{where}" if where else "")
        yield f"brush weights {what}", edited(session, weights, bad), name
    yield (
        "l_max big",
        edited(session, ("operations", falloff, "l_max"), 1e300),
        f"operations[{falloff}].l_max",
    )
    yield (
        "falloff eps",
        edited(session, ("operations", falloff, "falloff", "eps"), None),
        f"operations[{falloff}].falloff.eps",
    )
    yield (
        "spline rho",
        edited(session, ("operations", falloff, "falloff", "curves", 0, "rho"), 5),
        f"operations[{falloff}].falloff.curves[0].rho",
    )
    yield (
        "weights huge",
        edited(session, ("operations", falloff, "brush_weights"), {"grab": [HUGE] * 5}),
        f"operations[{falloff}].brush_weights.grab",
    )
    yield (
        "material huge",
        edited(session, ("settings", "material", "voigt"), (np.eye(6) * HUGE).tolist()),
        "settings.material.voigt",
    )


def test_every_broken_session_field_is_named_and_the_mesh_survives(sphere, recorded):
    vertices, faces = sphere
    cases = list(hostile_sessions(recorded))
    assert len(cases) > 40
    for name, data, parameter in cases:
        target = Sculptor(vertices, faces)
        target.apply_brush(Brush("grab"), [BrushEvent(vertices[3], [0.05, 0.0, 0.0])])
        before = target.vertices.copy()
        with pytest.raises(ParameterError) as info:
            # the schema refuses it before anything is applied, or (a value too large for this
            # model) the replay refuses it and rolls back
            parse_session(data)
            fresh = Sculptor.from_session(data, vertices, faces)
            fresh.replay(data["operations"])
        assert info.value.parameter.startswith(parameter), (name, info.value.parameter)
        assert parameter.rstrip(".") in str(info.value), (name, str(info.value))
        if parameter.startswith("operations["):  # replay alone refuses it too
            with pytest.raises(ParameterError) as info:
                target.replay(data["operations"])
            assert info.value.parameter.startswith(parameter), (name, info.value.parameter)
        assert np.array_equal(target.vertices, before), name
        assert target.history.undo_labels == ["Wide grab stroke"], name


def test_the_recorded_session_itself_replays(sphere, recorded):
    vertices, faces = sphere
    again = Sculptor.from_session(recorded, vertices, faces)
    again.replay(recorded["operations"])
    assert again.session()["operations"] == recorded["operations"]


@pytest.mark.parametrize(
    ("make", "parameter"),
    [
        (lambda s, v: s.apply_brush(Brush("grab"), [BrushEvent(v[0], [0, HUGE, 0])]), "delta"),
        (
            lambda s, v: s.apply_brush(
                Brush("grab", strength=1000), [BrushEvent(v[0], [0, 10.0, 0])]
            ),
            "delta",
        ),
        (lambda s, v: s.apply_brush(Brush("grab", strength=HUGE), []), "strength"),
        (lambda s, v: s.apply_brush(Brush("twist"), [BrushEvent(v[0], amount=HUGE)]), "amount"),
        (
            lambda s, v: s.apply_brush(
                Brush("scale", strength=100), [BrushEvent(v[0], amount=50.0)]
            ),
            "amount",
        ),
        (lambda s, v: s.apply_brush(Brush("pinch"), [BrushEvent([HUGE, 0, 0])]), "center"),
        (lambda s, v: s.apply_brush(Brush(), [BrushEvent([0, HUGE, 0], [0, 1, 0])]), "center"),
        (lambda s, v: s.apply_brush(Brush("twist"), [BrushEvent(v[0], axis=[0, 0, 0])]), "axis"),
        (lambda s, v: s.apply_brush(Brush("grab", radius=HUGE), []), "radius"),
        (lambda s, v: s.apply_brush(Brush("grab", substeps=1e300), []), "substeps"),
        (lambda s, v: s.add_constraint([1e300, 0, 0]), "point"),
        (lambda s, v: s.add_constraint([HUGE, 0, 0]), "point"),
        (lambda s, v: (s.add_constraint(v[0]), s.drag_constraint(0, [0, HUGE, 0])), "delta"),
        (lambda s, v: (s.add_constraint(v[0]), s.drag_constraint(0.5, [0, 0.1, 0])), "index"),
        (lambda s, v: (s.add_constraint(v[0]), s.drag_constraint(1, [0, 0.1, 0])), "index"),
        (lambda s, v: s.remove_constraint(0), "index"),
        (lambda s, v: s.change_settings(constraint_radius=HUGE), "constraint_radius"),
        (lambda s, v: s.change_settings(material=Material.isotropic(HUGE, 0.3)), "material"),
        (
            lambda s, v: s.change_settings(
                falloff=GaussianRadial(1.0), l_max=2, brush_weights={"grab": [1.0, HUGE, 1.0, 1.0]}
            ),
            "grab",  # brush_weights.grab
        ),
    ],
)
def test_extreme_values_are_refused_naming_the_field(sphere, make, parameter):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[3], [0.05, 0.0, 0.0])])
    before = sculptor.vertices.copy()
    with pytest.raises(ParameterError) as info:
        make(sculptor, sculptor.vertices)
    assert info.value.parameter.split(".")[-1] == parameter
    assert parameter in str(info.value)
    assert np.array_equal(sculptor.vertices, before)
    assert np.all(np.isfinite(sculptor.vertices))
    # a pin added before the refused step is an undo step of its own
    assert [k for k in sculptor.history.undo_labels if k != "add pin"] == ["Wide grab stroke"]
    assert not sculptor.in_stroke


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_huge_axes_and_directions_still_give_a_finite_unit_load(sphere, kind):
    vertices, faces = sphere
    results = []
    for scale in (1.0, 1e300, 1e-300):
        sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
        event = BrushEvent(
            vertices[0],
            amount=0.1,
            axis=scale * np.array([0.0, 0.6, 0.8]),
            direction=scale * np.array([1.0, 0.0, 0.0]),
        )
        sculptor.apply_brush(Brush(kind, radius=0.3), [event])
        results.append(sculptor.vertices.copy())
    assert np.all(np.isfinite(results))
    assert np.allclose(results[1], results[0], atol=1e-12)
    assert np.allclose(results[2], results[0], atol=1e-12)


def test_largest_accepted_magnitudes_give_finite_vertices(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, material=ANISOTROPIC)
    size = sculptor.model_size
    everywhere = dict(influence=np.inf, radius=0.3)
    sculptor.apply_brush(Brush("grab", **everywhere), [BrushEvent(vertices[0], [0, 999 * size, 0])])
    for kind in ("scale", "twist", "pinch"):
        for amount in (-100.0, 100.0):
            event = BrushEvent(vertices[1], amount=amount)
            sculptor.apply_brush(Brush(kind, **everywhere), [event])
    sculptor.add_constraint([999 * size, 0, 0])
    assert np.all(np.isfinite(sculptor.vertices))


@pytest.mark.parametrize(
    ("text", "parameter"),
    [
        ('"version": "2"', "version"),
        ('"version": null', "version"),
        ('"version": 1.5', "version"),
        ('"l_max": "8"', "l_max"),
        ('"l_max": 1e300', "l_max"),
        ('"degree_weights": 7', "degree_weights"),
        ('"name": 7', "name"),
        ('"brush": {"substeps": 1e300}', "brush.substeps"),
        ('"brush": {"radius": 1e200}', "brush.radius"),
        ('"brush": []', "brush"),
        ('"material": {"voigt": "steel"}', "material.voigt"),
        ('"material": null', "material"),
        ('"falloff": {"type": "gaussian"}', "falloff.eps"),
        ('"falloff": {"type": "multiscale", "eps": 1}', "falloff.type"),
        ('"colour": "red"', "colour"),
    ],
)
def test_broken_presets_raise_value_error_naming_the_field(tmp_path, text, parameter):
    good = Preset("p", ANISOTROPIC).to_dict()
    key = text.split(":")[0].strip('"')
    good.pop(key, None)
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(good)[:-1] + ", " + text + "}")
    with pytest.raises(ValueError) as info:
        load_preset(path)
    assert isinstance(info.value, ParameterError)
    assert info.value.parameter == parameter
    assert "broken.json" in str(info.value) and parameter in str(info.value)


def test_non_utf8_files_are_refused_with_a_message(tmp_path):
    path = tmp_path / "corrupt.json"
    path.write_bytes(b'{"format": "gogreen-session", "x": "\xff\xfe"}')
    with pytest.raises(ValueError, match=r"corrupt\.json: not a session file \(not UTF-8"):
        load_session(path)
    with pytest.raises(ValueError, match=r"corrupt\.json: not a preset file \(not UTF-8"):
        load_preset(path)


# -- command line ---------------------------------------------------------------------------
@pytest.fixture
def mesh_file(tmp_path, sphere):
    path = tmp_path / "sphere.obj"
    save_mesh(MeshData(vertices=sphere[0], faces=sphere[1]), path)
    return path


def run(args, capsys) -> tuple[int, str]:
    status = main([str(a) for a in args])
    return status, capsys.readouterr().err


@pytest.mark.parametrize(
    ("option", "content", "message"),
    [
        ("--material", "[1, 2, 3]", "--material: the file must be an object (got list)"),
        ("--material", "7", "--material: the file must be an object (got int)"),
        ("--material", '{"voigt": [1, 2]}', "--material.voigt must be a 6×6 matrix"),
        ("--material", "{", "not valid JSON"),
        ("--falloff", "[1, 2]", "--falloff: the file must be an object (got list)"),
        ("--falloff", "2.5", "--falloff: the file must be an object (got float)"),
        ("--falloff", '{"type": "spline", "eps": 1}', "--falloff.curves is missing"),
    ],
)
def test_cli_json_options_exit_2_naming_the_option(
    tmp_path, mesh_file, capsys, option, content, message
):
    data = tmp_path / "value.json"
    data.write_text(content)
    out = tmp_path / "out.obj"
    out.write_text("precious")
    args = ["deform", mesh_file, "-o", out, "--center", 0, 0, 1, "--delta", 0, 0.1, 0]
    status, err = run([*args, option, data], capsys)
    assert status == 2
    assert message in err and "Traceback" not in err
    assert out.read_text() == "precious"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--delta", "0", "inf", "0"], "--delta must be finite"),
        (["--delta", "0", "1e200", "0"], "--delta is too large (|delta| = 1e+200"),
        (["--delta", "0", "10", "0", "--strength", "1000"], "--delta × brush strength must be"),
        (["--center", "1e200", "0", "0"], "--center is too far from the model"),
        (["--center", "nan", "0", "0"], "--center must be finite"),
        (["--strength", "1e200"], "strength must be ≤ 1000"),
        (["--substeps", "100000"], "substeps must be ≤ 1000"),
        (["--brush", "twist", "--amount", "inf"], "--amount must be finite"),
        (["--brush", "twist", "--amount", "1e200"], "--amount must be ≤ 100"),
        (["--brush", "pinch", "--amount", "1", "--axis", "0", "0", "0"], "--axis must be nonzero"),
        (["--l-max", "1000"], "--l-max must be ≤ 60"),
        (["--radius", "1e200"], "radius must be ≤ 100"),
        (["--events", "0"], "--events must be ≥ 1"),
    ],
)
def test_cli_extreme_values_exit_2_naming_the_option(tmp_path, mesh_file, capsys, extra, message):
    out = tmp_path / "out.obj"
    args = ["deform", mesh_file, "-o", out, "--center", 0, 0, 1, "--delta", 0, 0.1, 0]
    # later options override the defaults above
    status, err = run([*args, *extra], capsys)
    assert status == 2, err
    assert message in err and "Traceback" not in err
    assert not out.exists()


def test_cli_replay_of_hostile_sessions_exits_2(tmp_path, mesh_file, capsys, recorded):
    cases = list(hostile_sessions(recorded))
    out = tmp_path / "out.obj"
    session = tmp_path / "s.json"
    for name, data, parameter in cases[:: max(1, len(cases) // 12)]:
        session.write_text(json.dumps(data))
        status, err = run(["replay", session, mesh_file, "-o", out, "-q"], capsys)
        assert status == 2, name
        assert "s.json" in err and parameter.rstrip(".") in err, (name, err)
        assert not out.exists()
    session.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00")
    status, err = run(["replay", session, mesh_file, "-o", out, "-q"], capsys)
    assert status == 2 and "not UTF-8" in err
    assert not out.exists()
