"""The Blender extension's logic without Blender: the modal stroke driven by synthetic events,
the background jobs, the settings → engine mapping, the brush circle's geometry.

These modules import no ``bpy``, so this file runs in the main suite and again in the
Blender one (``.venv-blender``); ``test_blender_addon.py`` tests them inside Blender.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Material, ParameterError, Sculptor
from gogreen_core.interaction.tools import PIXELS_PER_UNIT_AMOUNT
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.engine_settings import EngineSettings

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the extension's folder is no installed package
    sys.path.insert(0, str(ROOT))

from gogreen_blender import drawing, engine, jobs  # noqa: E402
from gogreen_blender.modal import (  # noqa: E402
    CANCELLED,
    FINISHED,
    RUNNING,
    InputEvent,
    ModalStroke,
)

#: Pixels per model unit of the fake orthographic top view, and its centre pixel.
SCALE, CX, CY = 200.0, 400.0, 300.0


class TopView:
    """A fake orthographic view looking down -z at the unit sphere (region y up)."""

    def to_world(self, x: float, y: float) -> tuple[float, float]:
        return (x - CX) / SCALE, (y - CY) / SCALE

    def to_region(self, point) -> tuple[float, float]:
        return CX + SCALE * point[0], CY + SCALE * point[1]

    def pick(self, x, y):
        px, py = self.to_world(x, y)
        r2 = px * px + py * py
        return None if r2 >= 1.0 else np.array([px, py, np.sqrt(1.0 - r2)])

    def drag_point(self, x, y, depth):
        px, py = self.to_world(x, y)
        return np.array([px, py, float(depth[2])])

    def axes(self):
        return np.array([0.0, 0.0, -1.0]), np.array([1.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def sphere():
    return icosphere(2)


def _sculptor(sphere, l_max: int = 4) -> Sculptor:
    vertices, faces = sphere
    return Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4), l_max=l_max)


def press(x, y, **kw):
    return InputEvent("LEFTMOUSE", "PRESS", x, y, **kw)


def move(x, y, **kw):
    return InputEvent("MOUSEMOVE", "NOTHING", x, y, **kw)


TICK = InputEvent("TIMER", "NOTHING")


def release(x, y):
    return InputEvent("LEFTMOUSE", "RELEASE", x, y)


def test_a_drag_is_one_stroke_whose_grabbed_point_follows_the_cursor(sphere):
    sculptor = _sculptor(sphere)
    before = sculptor.vertices.copy()
    stroke = ModalStroke(sculptor, Brush("grab", radius=0.1), TopView())
    assert stroke.start(press(CX, CY))
    for dx in (5, 10, 15, 20):
        assert stroke.handle(move(CX + dx, CY)) == RUNNING
        assert stroke.handle(TICK) == RUNNING
    assert stroke.handle(release(CX + 20, CY)) == FINISHED
    assert stroke.events_applied == 4
    assert len(sculptor.operations) == 1  # one stroke (one undo step) for the whole drag
    top = int(np.argmax(before[:, 2]))  # the vertex under the press (the pole)
    np.testing.assert_allclose(sculptor.vertices[top] - before[top], [20 / SCALE, 0, 0], atol=1e-3)
    np.testing.assert_allclose(stroke.center, [20 / SCALE, 0, 1.0])


def test_a_draw_stroke_follows_the_surface_not_the_drag_plane(sphere):
    """A paint brush's moves are picked on the surface: across the top of the sphere the
    drag plane through the press point (z = 0.6) would leave it a brush radius behind."""
    sculptor = _sculptor(sphere)
    before = sculptor.vertices.copy()
    stroke = ModalStroke(sculptor, Brush("draw", radius=0.05), TopView())
    assert stroke.start(press(CX - 160, CY))
    for dx in range(10, 330, 10):
        stroke.handle(move(CX - 160 + dx, CY))
        stroke.handle(TICK)
    assert stroke.handle(release(CX + 160, CY)) == FINISHED
    raised = np.linalg.norm(sculptor.vertices, axis=1) - np.linalg.norm(before, axis=1)
    top = int(np.argmax(before[:, 2]))  # the pole, halfway along the stroke
    assert raised[top] > 0.01


def test_moves_are_coalesced_the_newest_applies_at_the_tick(sphere):
    sculptor = _sculptor(sphere)
    stroke = ModalStroke(sculptor, Brush("grab", radius=0.1), TopView())
    stroke.start(press(CX, CY))
    for dx in range(1, 30):
        stroke.handle(move(CX + dx, CY))
    assert stroke.events_applied == 0 and not stroke.take_changed()
    stroke.handle(TICK)
    assert stroke.events_applied == 1 and stroke.take_changed()
    stroke.handle(TICK)  # nothing new recorded
    assert stroke.events_applied == 1 and not stroke.take_changed()
    # a release applies the move recorded after the last tick before it ends the stroke
    stroke.handle(move(CX + 40, CY))
    assert stroke.handle(release(CX + 40, CY)) == FINISHED
    assert stroke.events_applied == 2
    np.testing.assert_allclose(stroke.center, [40 / SCALE, 0, 1.0])


def test_the_strokes_events_are_the_engines(sphere):
    """The modal stroke sends the engine what the desktop app's stroke logic would: replaying
    its logged events through Sculptor.apply_brush gives the same vertices, bit for bit."""
    sculptor = _sculptor(sphere)
    brush = Brush("grab_biscale", radius=0.1, strength=0.8)
    stroke = ModalStroke(sculptor, brush, TopView())
    stroke.start(press(CX + 10, CY - 20))
    for dx, dy in ((5, 3), (12, 9), (20, 11)):
        stroke.handle(move(CX + 10 + dx, CY - 20 + dy))
        stroke.handle(TICK)
    stroke.handle(release(CX + 30, CY - 9))
    (logged,) = sculptor.operations
    replay = _sculptor(sphere)
    replay.apply_brush(brush, list(logged.events))
    assert np.array_equal(replay.vertices, sculptor.vertices)


@pytest.mark.parametrize("cancel", ["ESC", "RIGHTMOUSE"])
def test_esc_or_right_click_cancels_the_stroke_exactly(sphere, cancel):
    sculptor = _sculptor(sphere)
    before = sculptor.vertices.copy()
    stroke = ModalStroke(sculptor, Brush("grab", radius=0.1), TopView())
    stroke.start(press(CX, CY))
    stroke.handle(move(CX + 30, CY))
    stroke.handle(TICK)
    assert not np.array_equal(sculptor.vertices, before)
    assert stroke.handle(InputEvent(cancel, "PRESS", CX + 30, CY)) == CANCELLED
    assert np.array_equal(sculptor.vertices, before)
    assert stroke.take_changed()  # the caller writes the restored vertices back
    assert sculptor.operations == [] and not sculptor.in_stroke


def test_other_events_wait_for_the_end_of_the_stroke(sphere):
    sculptor = _sculptor(sphere)
    stroke = ModalStroke(sculptor, Brush("grab", radius=0.1), TopView())
    stroke.start(press(CX, CY))
    for event in (
        InputEvent("A", "PRESS"),
        InputEvent("MIDDLEMOUSE", "PRESS", CX, CY),
        InputEvent("ESC", "RELEASE"),
        InputEvent("WHEELUPMOUSE", "PRESS"),
    ):
        assert stroke.handle(event) == RUNNING
    assert sculptor.in_stroke


def test_a_press_off_the_mesh_starts_nothing(sphere):
    sculptor = _sculptor(sphere)
    stroke = ModalStroke(sculptor, Brush("grab"), TopView())
    assert not stroke.start(press(CX + 1.5 * SCALE, CY))
    assert not sculptor.in_stroke


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_affine_brushes_take_the_drag_length_and_ctrl_inverts(sphere, kind):
    results = {}
    for ctrl in (False, True):
        sculptor = _sculptor(sphere)
        stroke = ModalStroke(sculptor, Brush(kind, radius=0.15), TopView())
        stroke.start(press(CX, CY, ctrl=ctrl))
        stroke.handle(move(CX + 25, CY + 4, ctrl=ctrl))
        stroke.handle(TICK)
        stroke.handle(release(CX + 25, CY + 4))
        (logged,) = sculptor.operations
        (event,) = logged.events
        # the drag's length (25 px right, 4 down), + as it sets off right; Ctrl inverts
        length = np.hypot(25, 4)
        assert event.amount == pytest.approx((-length if ctrl else length) / PIXELS_PER_UNIT_AMOUNT)
        np.testing.assert_allclose(event.center, [0, 0, 1])  # affine brushes stay at the press
        np.testing.assert_allclose(event.axis, [0, 0, -1])
        results[ctrl] = sculptor.vertices.copy()
    assert not np.array_equal(results[False], results[True])


def test_pen_pressure_scales_the_step(sphere):
    deltas = {}
    for pressure in (1.0, 0.5):
        sculptor = _sculptor(sphere)
        stroke = ModalStroke(sculptor, Brush("grab", radius=0.1), TopView())
        stroke.start(press(CX, CY, pressure=pressure))
        stroke.handle(move(CX + 20, CY, pressure=pressure))
        stroke.handle(release(CX + 20, CY))
        (logged,) = sculptor.operations
        deltas[pressure] = logged.events[0].delta
    np.testing.assert_allclose(deltas[0.5], 0.5 * deltas[1.0])


def test_an_event_the_engine_refuses_leaves_the_vertices(sphere):
    sculptor = _sculptor(sphere)
    before = sculptor.vertices.copy()
    stroke = ModalStroke(sculptor, Brush("grab", radius=0.1, strength=1000.0), TopView())
    stroke.start(press(CX, CY))
    stroke.handle(move(CX + 1e9, CY))  # a cursor far beyond the reach the engine accepts
    with pytest.raises(ValueError, match="delta"):
        stroke.handle(TICK)
    assert np.array_equal(sculptor.vertices, before)
    stroke.cancel()
    assert not sculptor.in_stroke


# -- jobs ------------------------------------------------------------------------------------
def test_a_job_runs_on_a_worker_thread_and_is_delivered_on_poll():
    runner = jobs.JobRunner()
    started, release_job = threading.Event(), threading.Event()
    delivered = []

    def work(progress):
        started.set()
        progress(0.25)
        release_job.wait(5)
        return threading.current_thread().name

    job = jobs.Job("Working", work, delivered.append)
    assert runner.submit(job)
    assert started.wait(5)
    assert runner.busy is job and job.status() == "Working: 25 %"
    assert not runner.submit(jobs.Job("Another", lambda p: None))  # one at a time
    assert not jobs.ENGINE_LOCK.acquire(blocking=False)  # strokes must wait
    assert runner.poll() is None and delivered == []
    release_job.set()
    job.wait(5)
    assert runner.poll() is job and delivered == [job]
    assert job.result.startswith("gogreen") and job.error is None
    assert runner.busy is None and runner.poll() is None
    assert jobs.ENGINE_LOCK.acquire(blocking=False)
    jobs.ENGINE_LOCK.release()


def test_a_failing_job_reports_its_error_and_the_runner_goes_on():
    runner = jobs.JobRunner()

    def work(_progress):
        raise RuntimeError("no convergence")

    job = jobs.Job("Homogenizing", work)
    runner.submit(job, threaded=False)
    assert job.finished and isinstance(job.error, RuntimeError)
    assert job.status().startswith("Homogenizing: ")
    assert runner.poll() is job
    assert runner.submit(jobs.Job("Next", lambda p: 1), threaded=False)
    assert runner.wait().result == 1


def test_a_job_without_progress_shows_its_time():
    job = jobs.Job("Compiling", lambda p: time.sleep(0))
    job.started -= 12.3
    assert job.status() == "Compiling: 12 s"


# -- settings → engine ----------------------------------------------------------------------
def test_events_json_reads_the_session_event_format():
    text = json.dumps(
        [
            {"center": [0, 0, 1], "delta": [0.1, 0, 0]},
            {"center": [0, 0, 1], "amount": 0.2, "axis": [0, 1, 0], "radius_factor": 0.5},
        ]
    )
    first, second = engine.events_from_json(text)
    assert np.array_equal(first.delta, [0.1, 0, 0]) and second.axis.tolist() == [0, 1, 0]
    assert second.radius_factor == 0.5 and second.amount == 0.2


@pytest.mark.parametrize(
    ("text", "parameter"),
    [
        ("not json", "events"),
        ('{"center": [0, 0, 0]}', "events"),
        ('[{"center": [0, 0, 0]}, {"delta": [1, 0, 0]}]', "events[1].center"),
        ('[{"center": [0, 0, 0], "delta": [1, 0]}]', "events[0].delta"),
        ('[{"center": [0, 0, NaN]}]', "events[0].center"),
        ('[{"center": [0, 0, 0], "speed": 3}]', "events[0].speed"),
    ],
)
def test_bad_events_are_named(text, parameter):
    with pytest.raises(ParameterError) as info:
        engine.events_from_json(text)
    assert info.value.parameter == parameter


def test_material_json_keeps_every_bit():
    material = Material.orthotropic((1.0, 2.3, 7.1), (0.5, 0.61, 0.43), (0.3, 0.11, 0.07))
    material = engine.rotated_material(material, (0.3, -0.2, 1.1))
    assert engine.material_from_json(engine.material_to_json(material)) == material
    with pytest.raises(ParameterError, match="no preset material"):
        engine.material_from_json("", "preset material")
    with pytest.raises(ParameterError, match="not a valid stiffness"):
        engine.material_from_json('{"voigt": [[1, 2], [3, 4]]}')


def test_euler_angles_turn_the_material_axes_as_blender_does():
    # XYZ Euler: about x first, then y, then z (fixed axes); z by 90° takes x to y
    np.testing.assert_allclose(
        engine.euler_matrix((0, 0, np.pi / 2)) @ [1, 0, 0], [0, 1, 0], atol=1e-15
    )
    a, b, c = 0.3, -0.7, 1.2
    rx = engine.euler_matrix((a, 0, 0))
    ry = engine.euler_matrix((0, b, 0))
    rz = engine.euler_matrix((0, 0, c))
    np.testing.assert_allclose(engine.euler_matrix((a, b, c)), rz @ ry @ rx, atol=1e-15)
    stiff_z = Material.orthotropic((1.0, 1.0, 10.0), (0.5, 0.5, 0.4), (0.3, 0.1, 0.1))
    turned = engine.rotated_material(stiff_z, (np.pi / 2, 0, 0))  # z → -y
    young = turned.directional_young(np.eye(3))
    assert young[1] == pytest.approx(10.0) and young[2] == pytest.approx(1.0)


def test_orthotropic_errors_name_the_material():
    with pytest.raises(ParameterError, match="Poisson") as info:
        engine.orthotropic_material((1.0, 100.0, 1.0), (1, 1, 1), (0.9, 0.1, 0.1))
    assert info.value.parameter == "material"


def test_falloffs_and_mirrors():
    assert engine.falloff_from("GAUSSIAN").kind_name == "gaussian"
    assert engine.falloff_from("KELVINLET").kind_name == "kelvinlet"
    with pytest.raises(ParameterError, match="no falloff curve"):
        engine.falloff_from("CUSTOM", "")
    assert engine.mirror_axes(True, False, True) == "xz"


def test_degree_weights_of_every_brush_and_the_automatic_influence(sphere):
    assert engine.brush_weights_from("", 4) == {}
    weights = engine.brush_weights_from('{"pinch": [1, 0.25, 1, 1, 1, 1]}', 4)
    assert weights == {"pinch": (1.0, 0.25, 1.0, 1.0, 1.0, 1.0)}
    # stored for l_max 4, read for 6: the degrees both have kept, the new ones the defaults
    assert engine.brush_weights_from('{"pinch": [1, 0.25, 1, 1, 1, 1]}', 6)["pinch"][:2] == (
        1.0,
        0.25,
    )
    with pytest.raises(ParameterError, match="stored weights"):
        engine.brush_weights_from('{"pinch": [1, "x"]}', 4)
    with pytest.raises(ParameterError, match="stored weights"):
        engine.brush_weights_from("[1, 2]", 4)
    vertices, faces = sphere
    default = engine.default_settings(6).engine_settings
    stored = engine.brush_weights_from('{"pinch": [1, 16, 1, 1, 1, 1, 1, 1]}', 6)
    pinch = Brush("pinch", radius=0.2)
    settings = engine.SculptSettings(pinch, default.replace(brush_weights=stored))
    events = [BrushEvent(center=vertices[0], amount=0.3, axis=np.array([0.0, 0.2, 1.0]))]
    reference = Sculptor(vertices, faces, settings=settings.engine_settings)
    reference.origin = np.zeros(3)
    reference.apply_brush(settings.brush, events)
    assert np.array_equal(engine.stroke(vertices, faces, settings, events), reference.vertices)
    plain = engine.SculptSettings(settings.brush, default)
    assert not np.array_equal(engine.stroke(vertices, faces, plain, events), reference.vertices)
    # the cursor's reach: the engine's automatic influence, or the brush's own number
    assert engine.influence_of(settings) == reference.influence(settings.brush) > 4.0
    fixed = dataclasses.replace(settings, brush=Brush("pinch", radius=0.2, influence=3.0))
    assert engine.influence_of(fixed) == 3.0


def test_stroke_is_the_engines_apply_brush(sphere):
    vertices, faces = sphere
    material, falloff = Material.cubic(3.0, 1.5, 0.4), engine.falloff_from("KELVINLET")
    settings = engine.SculptSettings(
        Brush("twist", radius=0.2, symmetry="x"),
        EngineSettings(material=material, falloff=falloff, l_max=4),
    )
    events = [BrushEvent(center=vertices[0], amount=0.3, axis=np.array([0.0, 0.2, 1.0]))]
    result = engine.stroke(vertices, faces, settings, events)
    reference = Sculptor(
        vertices,
        faces,
        material=material,
        l_max=4,
        falloff=falloff,
    )
    reference.origin = np.zeros(3)
    reference.apply_brush(settings.brush, events)
    assert np.array_equal(result, reference.vertices)
    with pytest.raises(ParameterError, match="at least one event"):
        engine.stroke(vertices, faces, settings, [])


def test_mirror_planes_go_through_the_object_origin():
    """Blender mirrors about the object's axes: on a sphere about the origin whose bounding box
    is off-centre (a lone vertex at x = 4), a mirrored grab moves each vertex as its mirror
    image about x = 0 (the desktop app mirrors about the centre of the bounding box)."""
    sphere_vertices, faces = icosphere(2)
    vertices = np.vstack([sphere_vertices, [4.0, 0.0, 0.0]])
    settings = dataclasses.replace(
        engine.default_settings(4), brush=Brush("grab", radius=0.05, symmetry="x")
    )
    grabbed = sphere_vertices[np.argmax(sphere_vertices @ [0.5, 0.0, 0.8])]
    event = BrushEvent(center=grabbed, delta=np.array([0.05, 0.0, 0.05]))
    moved = (engine.stroke(vertices, faces, settings, [event]) - vertices)[:-1]
    flip = np.array([-1.0, 1.0, 1.0])
    mirror = [
        int(np.argmin(np.linalg.norm(sphere_vertices - v * flip, axis=1))) for v in sphere_vertices
    ]
    assert np.abs(moved).max() > 0.04
    np.testing.assert_allclose(moved[mirror], moved * flip, atol=1e-12)


def test_ring_points_draw_a_closed_circle_in_the_view_plane():
    center = np.array([1.0, 2.0, 3.0])
    right, up = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    ring = drawing.ring_points(center, right, up, 0.5, segments=32)
    assert ring.shape == (33, 3)
    np.testing.assert_allclose(np.linalg.norm(ring - center, axis=1), 0.5)
    np.testing.assert_allclose(ring[0], ring[-1])
    np.testing.assert_allclose(ring[:, 0], 1.0)  # in the plane of right and up


def test_f_drags_a_value_on_screen_and_esc_puts_it_back():
    from gogreen_blender.radial import RadialControl

    control = RadialControl(50.0, 1.0, 500.0, 1.0, x=300.0, y=200.0)  # radius 50 px
    assert control.center == (250.0, 200.0) and control.pixels == 50.0  # the mouse on the rim
    assert control.handle(move(250.0, 280.0)) == RUNNING
    assert control.value == pytest.approx(80.0)
    assert control.handle(move(250.0, 200.0)) == RUNNING
    assert control.value == 1.0  # kept in its range
    assert control.handle(InputEvent("ESC", "PRESS")) == CANCELLED
    assert control.value == 50.0
    strength = RadialControl(0.5, 0.0, 10.0, 200.0, x=100.0, y=100.0)
    strength.handle(move(100.0 - 100.0 + 150.0, 100.0))  # 150 px from the centre
    assert strength.value == pytest.approx(0.75)
    for confirm in ("LEFTMOUSE", "RET"):
        assert strength.handle(InputEvent(confirm, "PRESS")) == FINISHED
    with pytest.raises(ValueError, match="pixels_per_unit"):
        RadialControl(1.0, 0.0, 1.0, 0.0, 0.0, 0.0)
