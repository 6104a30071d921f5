"""Stroke, pin and cursor controllers driven by plain events: no window, no Qt."""

import numpy as np
import pytest

from gogreen_core.interaction.tools import (
    PIXELS_PER_UNIT_AMOUNT,
    CursorState,
    PointerEvent,
    SculptTools,
)
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import Brush
from gogreen_core.sculpt.sculptor import Sculptor

NORTH = np.array([0.0, 0.0, 1.0])
GRAB = Brush("grab", radius=0.1, influence=4.0)  # the reach these tests measure


@pytest.fixture
def sculptor():
    vertices, faces = icosphere(3)
    return Sculptor(vertices, faces)


def at(point, screen=(0.0, 0.0), normal=None, pressure=1.0) -> PointerEvent:
    return PointerEvent(screen, np.asarray(point, float), normal, pressure=pressure)


def tools_for(sculptor, brush=GRAB, **kwargs) -> SculptTools:
    return SculptTools(sculptor, brush=lambda: brush, **kwargs)


def test_grab_stroke_follows_the_cursor_and_is_one_undo_step(sculptor):
    tools = tools_for(sculptor)
    before = sculptor.vertices.copy()
    top = int(np.argmax(before[:, 2]))
    start = before[top]
    assert tools.press(at(start, normal=NORTH)).cursor is not None
    assert tools.dragging and sculptor.in_stroke
    targets = [start + k * np.array([0.0, 0.0, 0.05]) for k in (1, 2, 3)]
    for k, target in enumerate(targets):
        tools.move(at(target, screen=(0.0, -10.0 * (k + 1))))
        update = tools.flush()
        assert update.moved is not None and update.step_seconds > 0
    tools.release()
    assert not tools.dragging and not sculptor.in_stroke
    assert np.allclose(sculptor.vertices[top], targets[-1], atol=1e-9)
    assert sculptor.undo() is not None  # one undo step for the whole stroke
    assert np.array_equal(sculptor.vertices, before)


def test_moves_are_coalesced_and_the_last_position_is_always_applied(sculptor):
    tools = tools_for(sculptor)
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start))
    for k in range(1, 21):  # 20 moves arrive before the event loop gets to apply one
        tools.move(at(start + 0.004 * k * NORTH, screen=(0.0, -k)))
    assert tools.received == 20 and tools.processed == 0
    tools.flush()
    assert tools.processed == 1 and not tools.has_pending
    assert tools.flush().moved is None  # nothing left to do: no backlog
    tools.move(at(start + 0.1 * NORTH))
    tools.release()  # applies the last recorded move before ending the stroke
    assert (tools.received, tools.processed) == (21, 2)
    assert np.allclose(sculptor.vertices[top], start + 0.1 * NORTH, atol=1e-9)


def test_affine_brush_takes_its_amount_from_the_screen_drag(sculptor):
    tools = tools_for(sculptor, Brush("scale", radius=0.2))
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start, screen=(100.0, 100.0)))
    event = PointerEvent(
        (100.0 + 0.5 * PIXELS_PER_UNIT_AMOUNT, 100.0),
        start,
        view_dir=-NORTH,
        screen_x=np.array([1.0, 0.0, 0.0]),
    )
    brush_event = tools.stroke.brush_event(event)
    assert brush_event.amount == pytest.approx(0.5)
    assert np.allclose(brush_event.center, start)
    tools.cancel()
    assert not sculptor.in_stroke


def test_pressure_scales_a_grab_step(sculptor):
    tools = tools_for(sculptor)
    start = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    tools.press(at(start))
    brush_event = tools.stroke.brush_event(at(start + 0.1 * NORTH, pressure=0.25))
    assert np.allclose(brush_event.delta, 0.025 * NORTH)
    tools.cancel()


def test_press_off_the_surface_or_before_ready_is_refused_with_a_message(sculptor):
    tools = tools_for(sculptor, ready=lambda: "kernels are still compiling")
    update = tools.press(at(sculptor.vertices[0]))
    assert update.error == "kernels are still compiling" and update.refused
    assert not tools.dragging
    tools.ready = lambda: None
    update = tools.press(PointerEvent((0.0, 0.0), None))
    assert update.error and "surface" in update.error and not sculptor.in_stroke


def test_engine_error_cancels_the_stroke_and_restores_the_mesh(sculptor):
    tools = tools_for(sculptor)
    before = sculptor.vertices.copy()
    start = before[int(np.argmax(before[:, 2]))]
    tools.press(at(start))
    tools.move(at(start + 0.05 * NORTH))
    tools.flush()
    tools.move(at(np.array([np.nan, 0.0, 0.0])))
    update = tools.flush()
    assert update.error and update.all_moved
    assert not tools.dragging and not sculptor.in_stroke
    assert np.array_equal(sculptor.vertices, before)


def test_pin_mode_adds_pins_and_drags_one_as_one_undo_step(sculptor):
    radii = []
    tools = tools_for(sculptor, first_pin_radius=lambda: radii.append(0.1))
    tools.mode = "pin"
    v = sculptor.vertices
    north, south = v[int(np.argmax(v[:, 2]))].copy(), v[int(np.argmin(v[:, 2]))].copy()
    for point in (north, south):
        assert tools.press(at(point)).pins_changed
        tools.release()
    assert radii == [0.1]  # only before the first pin
    assert len(sculptor.constraint_points) == 2
    before = sculptor.vertices.copy()
    assert not tools.press(at(north)).pins_changed  # on pin 0: grabs it, adds none
    for k in (1, 2, 3):
        tools.move(at(north + 0.03 * k * NORTH))
        update = tools.flush()
        assert update.pins_changed and update.all_moved
    tools.release()
    assert np.allclose(sculptor.constraint_points[0], north + 0.09 * NORTH)
    assert np.allclose(sculptor.constraint_points[1], south)
    assert len(sculptor.constraint_points) == 2
    sculptor.undo()  # the whole drag
    assert np.allclose(sculptor.vertices, before)
    assert np.allclose(sculptor.constraint_points[0], north)


def test_hover_places_and_hides_the_cursor_ring_at_the_brush_radius(sculptor):
    brush = Brush("grab", radius=0.05)
    tools = tools_for(sculptor, brush)
    tools.hover(at(NORTH, normal=NORTH))
    tools.hover(at(2 * NORTH, normal=NORTH))  # only the newest hover counts
    update = tools.flush()
    assert np.allclose(update.cursor.center, 2 * NORTH)
    assert update.cursor.radius == pytest.approx(brush.eps(sculptor.model_size))
    update = tools.flush()
    assert not update.changed
    tools.hover(PointerEvent((0.0, 0.0), None))
    assert tools.flush().hide_cursor


def test_ring_matrix_puts_the_unit_circle_on_the_tangent_plane():
    state = CursorState(np.array([1.0, 2.0, 3.0]), np.array([0.0, 0.0, 2.0]), 0.5)
    m = state.ring_matrix()
    ring = np.array([[np.cos(t), np.sin(t), 0.0, 1.0] for t in np.linspace(0, 6, 7)])
    world = (m @ ring.T).T[:, :3]
    assert np.allclose(np.linalg.norm(world[:, :2] - [1.0, 2.0], axis=1), 0.5)
    assert np.allclose(world[:, 2], 3.0 + 0.5e-3)


def test_cursor_carries_influence_and_a_falloff_profile(sculptor):
    brush = Brush("grab", radius=0.1, influence=3.0)
    tools = tools_for(sculptor, brush)
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))]
    tools.hover(at(top, normal=NORTH))
    state = tools.flush().cursor
    assert state.influence == 3.0 and state.radius == pytest.approx(0.1 * sculptor.model_size)
    profile = state.profile
    assert profile[0] == pytest.approx(1.0) and profile[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.all(np.diff(profile) <= 1e-12)  # the Kelvinlet-like field falls off
    assert 0.05 < profile[len(profile) // 3] < 1.0  # not the bare cutoff (1 up to half)


def test_smooth_cutoff_and_profile_without_kernels():
    from gogreen_core.interaction.tools import brush_profile
    from gogreen_core.sculpt.constraints import smooth_cutoff

    r = np.array([0.0, 0.5, 0.75, 1.0, 2.0])
    np.testing.assert_allclose(smooth_cutoff(r, 0.5, 1.0), [1.0, 1.0, 0.5, 0.0, 0.0])
    cutoff_only = brush_profile(None, 2.0, eps=0.1)  # an influence of 2 ε
    assert cutoff_only[0] == 1.0 and cutoff_only[-1] == 0.0


def test_affine_brush_cursor_stays_at_the_point_it_acts_on(sculptor):
    tools = tools_for(sculptor, Brush("twist", radius=0.1))
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    tools.press(at(top, normal=NORTH))
    tools.move(at(top + np.array([0.3, 0.0, 0.0]), screen=(40.0, 0.0)))
    update = tools.flush()
    assert update.moved is not None
    np.testing.assert_array_equal(update.cursor.center, top)
    tools.release()


def test_cursor_hide_and_refresh(sculptor):
    radius = {"r": 0.1}
    tools = SculptTools(sculptor, brush=lambda: Brush("grab", radius=radius["r"]))
    tools.hover(at([0.0, 0.0, 1.0], normal=NORTH))
    tools.flush()
    radius["r"] = 0.2
    assert tools.cursor.refresh().radius == pytest.approx(0.2 * sculptor.model_size)
    tools.cursor.hide()
    assert tools.cursor.state is None and tools.cursor.refresh() is None


class FakeBrushSettings:
    """Stands in for gogreen_core.interaction.settings.BrushSettings (plain attributes)."""

    def __init__(self):
        self.kind, self.radius, self.strength, self.influence = "grab", 0.1, 1.0, 4.0

    @property
    def brush(self):
        return Brush(self.kind, radius=self.radius, strength=self.strength)


def settings_tools(sculptor):
    settings = FakeBrushSettings()
    return SculptTools(sculptor, brush=lambda: settings.brush, settings=settings), settings


def test_f_drag_sets_the_radius_live_and_confirms_or_cancels(sculptor):
    tools, settings = settings_tools(sculptor)
    tools.hover(at([0.0, 0.0, 1.0], normal=NORTH))
    tools.flush()
    # the ring (centre (100, 100), 40 px) is under the pointer's start at its edge
    update = tools.start_value_drag("radius", (140.0, 100.0), (100.0, 100.0), 40.0)
    assert update.cursor.label == "Radius 0.1"
    update = tools.move_value_drag((180.0, 100.0))  # twice the distance: twice the radius
    assert settings.radius == pytest.approx(0.2) and update.cursor.label == "Radius 0.2"
    assert update.cursor.radius == pytest.approx(0.2 * sculptor.model_size)
    tools.finish_value_drag(confirm=True)
    assert settings.radius == pytest.approx(0.2) and tools.value_drag is None
    assert tools.cursor.state.label is None
    tools.start_value_drag("radius", (180.0, 100.0), (100.0, 100.0), 80.0)
    tools.move_value_drag((110.0, 100.0))
    assert settings.radius == pytest.approx(0.025)
    tools.finish_value_drag(confirm=False)  # Escape / right click
    assert settings.radius == pytest.approx(0.2)


def test_shift_f_drags_the_strength_and_clips(sculptor):
    tools, settings = settings_tools(sculptor)
    tools.start_value_drag("strength", (150.0, 100.0), (100.0, 100.0), 40.0)
    tools.move_value_drag((100.0, 200.0))  # 100 px from the centre, was 50 px: twice
    assert settings.strength == pytest.approx(2.0)
    tools.move_value_drag((100.0, 100.0))
    assert settings.strength == 0.0
    tools.finish_value_drag(confirm=True)
    assert settings.strength == 0.0


def test_number_keys_pick_the_brush_whose_row_has_them(sculptor):
    from gogreen_core.interaction.tools import NUMBER_KEYS, brush_for_key
    from gogreen_core.sculpt.brushes import BRUSH_ROWS

    tools, settings = settings_tools(sculptor)
    for row in BRUSH_ROWS:
        if row.number:
            assert tools.pick_brush(row.number) and settings.kind == row.kind
    # fixed per brush, not by table position: key 1 the local grab, 2 the wide one, 0 the mask
    assert [brush_for_key(k) for k in "120"] == ["grab_local", "grab", "mask"]
    assert set(NUMBER_KEYS) == set("1234567890")
    assert brush_for_key("a") is None and brush_for_key("11") is None


def test_ctrl_held_inverts_the_brush(sculptor):
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools = tools_for(sculptor)
    tools.press(at(start))
    ctrl = PointerEvent((0.0, -5.0), start + 0.02 * NORTH, modifiers=frozenset({"ctrl"}))
    tools.move(ctrl)
    tools.flush()
    tools.release()
    np.testing.assert_allclose(sculptor.vertices[top], start - 0.02 * NORTH, atol=1e-9)


def pen_tools(sculptor, **options):
    from gogreen_core.interaction.settings import PenSettings

    pen = PenSettings(**options)
    return SculptTools(sculptor, brush=lambda: GRAB, pen=lambda: pen)


def grab_once(tools, sculptor, pressure, step=0.02):
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start, pressure=pressure))
    tools.move(at(start + step * NORTH, screen=(0.0, -10.0), pressure=pressure))
    tools.flush()
    tools.release()
    return sculptor.vertices[top] - start


def test_pressure_drives_the_strength_only_when_toggled(sculptor):
    moved = grab_once(pen_tools(sculptor), sculptor, 0.5)
    np.testing.assert_allclose(moved, 0.01 * NORTH, atol=1e-9)
    sculptor.undo()
    moved = grab_once(pen_tools(sculptor, pressure_strength=False), sculptor, 0.5)
    np.testing.assert_allclose(moved, 0.02 * NORTH, atol=1e-9)


def pen_stroke(tools, sculptor, pressures, step=0.01):
    """A grab stroke up from the top vertex, one applied move per pressure; returns the
    vertices moved by each event and the events' radius factors, as the engine logged them."""
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start, pressure=pressures[0]))
    moved = []
    for k, pressure in enumerate(pressures, start=1):
        tools.move(at(start + k * step * NORTH, screen=(0.0, -10.0 * k), pressure=pressure))
        before = sculptor.vertices.copy()
        update = tools.flush()
        assert update.moved is not None
        moved.append(np.flatnonzero(np.any(sculptor.vertices != before, axis=1)))
    tools.release()
    stroke = sculptor.operations[-1]
    return moved, [event.radius_factor for event in stroke.events], start


def test_pressure_drives_the_radius_along_the_stroke(sculptor):
    tools = pen_tools(sculptor, pressure_radius=True, pressure_strength=False)
    pressures = [1.0, 0.8, 0.55, 0.3]
    moved, factors, start = pen_stroke(tools, sculptor, pressures)
    assert factors == pytest.approx(pressures)  # each event's radius follows the pen
    # the reach of each event (farthest moved vertex from the centre) shrinks with it
    eps = GRAB.eps(sculptor.model_size)
    reach = []
    for k, (indices, factor) in enumerate(zip(moved, factors, strict=True)):
        center = start + k * 0.01 * NORTH
        farthest = np.linalg.norm(sculptor.vertices[indices] - center, axis=1).max()
        assert farthest <= GRAB.influence * factor * eps + 0.01 + 1e-9  # the event's own ball
        reach.append(len(indices))
    assert reach == sorted(reach, reverse=True) and reach[-1] < 0.25 * reach[0]
    # the grabbed point still follows the pen exactly, whatever the radius
    top = int(np.argmax(sculptor.vertices[:, 2]))
    np.testing.assert_allclose(sculptor.vertices[top], start + 0.04 * NORTH, atol=1e-9)
    # the brush cursor shows the radius the latest event acted with, the full one after
    assert tools.stroke.radius is None
    tools.press(at(start, pressure=0.4))
    assert tools.cursor.state.radius == pytest.approx(0.4 * eps)
    assert tools.cursor.state.full_radius == pytest.approx(eps)  # the full ring, faint
    tools.move(at(start + 0.01 * NORTH, screen=(0.0, -10.0), pressure=0.0))
    assert tools.flush().cursor.radius == pytest.approx(0.1 * eps)  # a feather keeps a tenth
    tools.release()
    hovered = tools.cursor.place(start, NORTH)
    assert hovered.radius == pytest.approx(eps) and hovered.full_radius is None
    assert sculptor.operations[-1].events[0].radius_factor == pytest.approx(0.1)


def test_pressure_radius_off_keeps_the_radius_and_old_sessions(sculptor):
    tools = pen_tools(sculptor, pressure_radius=False, pressure_strength=False)
    _, factors, _ = pen_stroke(tools, sculptor, [1.0, 0.3])
    assert factors == [1.0, 1.0]
    assert all("radius_factor" not in e for e in sculptor.session()["operations"][-1]["events"])


def test_spacing_follows_the_pressure_scaled_radius(sculptor):
    tools = pen_tools(sculptor, spacing=0.5, pressure_radius=True)
    eps = GRAB.eps(sculptor.model_size)
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start, pressure=0.5))
    # 0.3 ε is past half of the half-pressure ε (0.25 ε): applied
    tools.move(at(start + 0.3 * eps * NORTH, screen=(0.0, -1.0), pressure=0.5))
    assert tools.flush().moved is not None
    tools.move(at(start + 0.6 * eps * NORTH, screen=(0.0, -2.0), pressure=1.0))
    assert tools.flush().moved is None  # 0.3 ε < 0.5 ε at full pressure: skipped
    tools.release()


def test_stabilizer_trails_the_pointer_by_the_lazy_radius(sculptor):
    tools = pen_tools(sculptor, lazy_radius=20.0)
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(PointerEvent((0.0, 0.0), start))
    tools.move(PointerEvent((15.0, 0.0), start + 0.015 * NORTH))  # within the rope: nothing
    assert tools.flush().moved is None
    tools.move(PointerEvent((40.0, 0.0), start + 0.04 * NORTH))  # the brush goes to 20 px
    assert tools.flush().moved is not None
    tools.release()
    np.testing.assert_allclose(sculptor.vertices[top], start + 0.02 * NORTH, atol=1e-9)


def test_spacing_skips_moves_shorter_than_a_fraction_of_eps(sculptor):
    tools = pen_tools(sculptor, spacing=0.5)
    eps = GRAB.eps(sculptor.model_size)
    top = int(np.argmax(sculptor.vertices[:, 2]))
    start = sculptor.vertices[top].copy()
    tools.press(at(start))
    tools.move(at(start + 0.3 * eps * NORTH, screen=(0.0, -1.0)))
    assert tools.flush().moved is None
    tools.move(at(start + 0.6 * eps * NORTH, screen=(0.0, -2.0)))
    assert tools.flush().moved is not None
    tools.move(at(start + 0.9 * eps * NORTH, screen=(0.0, -3.0)))  # 0.3 ε from the last
    assert tools.flush().moved is None
    tools.release()
    np.testing.assert_allclose(sculptor.vertices[top], start + 0.6 * eps * NORTH, atol=1e-9)


# -- affine brushes in any direction (issue 21 item 3) -------------------------------------------
def _affine_amounts(sculptor, kind, screens, start_screen=(100.0, 100.0)):
    """The amounts (and directions) of the events a drag through ``screens`` makes."""
    tools = tools_for(sculptor, Brush(kind, radius=0.2))
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    tools.press(at(top, screen=start_screen))
    events = []
    for screen in screens:
        event = PointerEvent(screen, top, view_dir=-NORTH, screen_x=np.array([1.0, 0.0, 0.0]))
        made = tools.stroke.brush_event(event)
        if made is not None:
            events.append(made)
    tools.cancel()
    return events


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_a_vertical_drag_drives_an_affine_brush_as_far_as_a_horizontal_one(sculptor, kind):
    """The walkthrough: a 140 px vertical pinch drag changed nothing."""
    up = _affine_amounts(sculptor, kind, [(100.0, 100.0 - 10.0 * k) for k in range(1, 15)])
    right = _affine_amounts(sculptor, kind, [(100.0 + 10.0 * k, 100.0) for k in range(1, 15)])
    down = _affine_amounts(sculptor, kind, [(100.0, 100.0 + 10.0 * k) for k in range(1, 15)])
    left = _affine_amounts(sculptor, kind, [(100.0 - 10.0 * k, 100.0) for k in range(1, 15)])
    drags = {"up": up, "right": right, "down": down, "left": left}
    total = {name: sum(e.amount for e in events) for name, events in drags.items()}
    assert total["up"] == pytest.approx(140.0 / PIXELS_PER_UNIT_AMOUNT)  # right or up: +
    assert total["right"] == pytest.approx(total["up"])
    assert total["down"] == pytest.approx(-total["up"])  # left or down: −
    assert total["left"] == pytest.approx(-total["up"])
    # pinch stretches along the drag: vertical for a vertical drag
    direction = up[-1].direction / np.linalg.norm(up[-1].direction)
    assert abs(direction @ np.cross(np.array([1.0, 0.0, 0.0]), -NORTH)) == pytest.approx(1.0)


def test_an_affine_drag_never_jumps_and_starts_over_at_the_press_point(sculptor):
    # out to the right, back through the press point, on to the left: the amount grows to
    # +80 px, falls back to 0 near the press point, then goes negative (a new drag)
    path = [(100.0 + x, 100.0) for x in (20, 40, 60, 80, 60, 40, 20, 1, -20, -40)]
    events = _affine_amounts(sculptor, "scale", path)
    cumulative = np.cumsum([e.amount for e in events]) * PIXELS_PER_UNIT_AMOUNT
    np.testing.assert_allclose(cumulative, [20, 40, 60, 80, 60, 40, 20, 0, -20, -40], atol=1e-9)
    steps = np.abs(np.diff(np.concatenate([[0.0], cumulative])))
    assert steps.max() <= 20.0 + 1e-9  # never more than the pointer moved


def test_a_stroke_that_changes_nothing_says_so_and_records_nothing(sculptor):
    tools = tools_for(sculptor, Brush("pinch", radius=0.2))
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    operations = len(sculptor.operations)
    tools.press(at(top, screen=(50.0, 50.0)))
    update = tools.release()  # a click: no drag
    assert update.note is not None and update.note.startswith("Nothing changed: the Pinch stroke")
    assert not sculptor.history.can_undo and len(sculptor.operations) == operations
    tools.press(at(top, screen=(50.0, 50.0)))
    tools.move(at(top, screen=(50.0, 10.0)))  # 40 px straight up
    update = tools.release()
    assert update.note is None and update.moved is not None
    assert sculptor.history.undo_labels == ["Pinch stroke"]
    assert len(sculptor.operations) == operations + 1


def test_nothing_changed_names_the_brush_by_its_row_label(sculptor):
    """The note names the brush as its toolbar button does ("Grab", "Wide grab"), not by its
    kind ("grab-local", "grab")."""
    top = sculptor.vertices[int(np.argmax(sculptor.vertices[:, 2]))].copy()
    for kind, label in (("grab_local", "Grab"), ("grab", "Wide grab")):
        tools = tools_for(sculptor, Brush(kind, radius=0.2))
        tools.press(at(top, screen=(50.0, 50.0)))
        update = tools.release()
        assert update.note is not None
        assert update.note.startswith(f"Nothing changed: the {label} stroke moved no vertex")


def test_the_cursor_carries_the_detail_size_while_dynamic_topology_is_on(sculptor):
    """Dynamic topology off: no detail; on: the detail size in model units, or without one
    the surface's own edge length (what a stroke remeshes to)."""
    from dataclasses import replace

    from gogreen_core.mesh.remesh import median_edge_length

    tools = tools_for(sculptor)
    tools.hover(at(NORTH, normal=NORTH))
    assert tools.flush().cursor.detail is None
    sculptor.apply_settings(replace(sculptor.settings, dynamic_topology=True))
    state = tools.cursor.refresh()
    own = median_edge_length(sculptor.vertices, sculptor.faces)
    assert state.detail == pytest.approx(own)
    sculptor.apply_settings(replace(sculptor.settings, detail_size=0.01))
    assert tools.cursor.refresh().detail == pytest.approx(0.01 * sculptor.model_size)
