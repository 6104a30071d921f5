"""The vertex mask: painted, erased, inverted, cleared; held vertices move under no brush and no
pin drag; every edit an undo step and a session record that replays bit for bit."""

import json

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.interaction.tools import PointerEvent, SculptTools
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import BRUSH_KINDS, BRUSH_TABLE
from gogreen_core.sculpt.brushes.paint import PAINT_AUTO_INFLUENCE


@pytest.fixture(scope="module")
def sphere():
    return icosphere(3)


def top_of(vertices):
    return vertices[int(np.argmax(vertices[:, 2]))]


def masked(sphere, radius=0.12):
    """A sculptor whose top is held (mask 1 near it, a soft rim)."""
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_brush(Brush("mask", radius=radius), [BrushEvent(top_of(vertices), amount=1.0)])
    return sculptor


def an_event(vertices):
    """One event every brush family takes: a grab motion, an affine amount with its axes."""
    top = top_of(vertices)
    return BrushEvent(
        top, [0.06, 0.03, 0.08], amount=0.25, axis=[0.0, 0.0, 1.0], direction=[1.0, 0.0, 0.0]
    )


def test_the_mask_brush_paints_with_the_cutoff_weight_and_ctrl_erases(sphere):
    vertices, _faces = sphere
    sculptor = masked(sphere)
    mask = sculptor.mask.values
    assert np.array_equal(sculptor.vertices, vertices)  # painting moves nothing
    distance = np.linalg.norm(vertices - top_of(vertices), axis=1)
    reach = PAINT_AUTO_INFLUENCE * 0.12 * sculptor.model_size  # automatic: 2ε
    assert np.all(mask[distance < 0.5 * reach] == 1.0)  # the inner half of the influence
    assert np.all(mask[distance >= reach] == 0.0)
    rim = (distance > 0.5 * reach) & (distance < reach)
    assert np.any((mask[rim] > 0) & (mask[rim] < 1))  # soft at the rim
    assert sculptor.mask.any and sculptor.history.undo_labels == ["Mask stroke"]
    # a negative amount (Ctrl) erases, clipped at 0
    sculptor.apply_brush(Brush("mask", radius=0.3), [BrushEvent(top_of(vertices), amount=-2.0)])
    assert not sculptor.mask.any and np.all(sculptor.mask.values == 0.0)
    with pytest.raises(ValueError, match="read-only"):
        sculptor.mask.values[0] = 1.0


@pytest.mark.parametrize("kind", BRUSH_KINDS)
def test_a_masked_region_moves_0_under_every_brush_of_the_table(sphere, kind):
    """Every row of the brush table (including brushes added later)."""
    vertices, _faces = sphere
    sculptor = masked(sphere)
    held = sculptor.mask.values == 1.0
    assert held.sum() > 10
    before = sculptor.vertices.copy()
    sculptor.apply_brush(Brush(kind, radius=0.15, symmetry="x"), [an_event(vertices)] * 3)
    assert np.array_equal(sculptor.vertices[held], before[held])  # bit for bit
    if kind != "mask":
        assert np.any(sculptor.vertices[~held] != before[~held]), "the brush moved nothing"


def test_the_table_is_iterated(sphere):
    """The parametrization above takes the table's kinds, so a new row is tested too."""
    assert [row.kind for row in BRUSH_TABLE] == list(BRUSH_KINDS)


def test_soft_mask_moves_vertices_part_of_the_way(sphere):
    vertices, faces = sphere
    free = Sculptor(vertices, faces)
    event = an_event(vertices)
    free.apply_brush(Brush("grab", radius=0.2), [event])
    half = Sculptor(vertices, faces)
    everywhere = Brush("mask", strength=0.5, influence=np.inf)
    half.apply_brush(everywhere, [BrushEvent(event.center, amount=1.0)])
    assert np.all(half.mask.values == 0.5)
    half.apply_brush(Brush("grab", radius=0.2), [event])
    np.testing.assert_allclose(
        half.vertices - vertices, 0.5 * (free.vertices - vertices), atol=1e-15
    )


def test_pins_drags_leave_masked_vertices(sphere):
    vertices, _faces = sphere
    sculptor = masked(sphere)
    held = sculptor.mask.values == 1.0
    before = sculptor.vertices.copy()
    pin = sculptor.add_constraint(top_of(vertices))
    u = sculptor.drag_constraint(pin, np.array([0.0, 0.1, 0.05]))
    assert np.array_equal(sculptor.vertices[held], before[held])
    assert np.all(u[held] == 0.0) and np.any(u[~held] != 0.0)


def test_mask_edits_are_undo_steps_that_leave_the_vertices(sphere):
    vertices, _faces = sphere
    sculptor = masked(sphere)
    painted = sculptor.mask.values.copy()
    sculptor.mask.invert()
    assert np.array_equal(sculptor.mask.values, 1.0 - painted)
    sculptor.mask.clear()
    assert not sculptor.mask.any
    sculptor.mask.clear()  # nothing masked: no step
    assert sculptor.history.undo_labels == ["Mask stroke", "invert mask", "clear mask"]
    versions = [sculptor.mask.version]
    assert sculptor.undo() == "clear mask"
    assert np.array_equal(sculptor.mask.values, 1.0 - painted)
    assert sculptor.undo() == "invert mask"
    assert np.array_equal(sculptor.mask.values, painted)
    assert sculptor.undo() == "Mask stroke"
    assert not sculptor.mask.any
    versions.append(sculptor.mask.version)
    assert versions[1] > versions[0]
    for label in ("Mask stroke", "invert mask", "clear mask"):
        assert sculptor.redo() == label
    assert not sculptor.mask.any and sculptor.redo() is None
    assert np.array_equal(sculptor.vertices, vertices)


def test_every_mask_operation_replays_bit_for_bit(sphere):
    vertices, faces = sphere
    sculptor = masked(sphere)
    top = top_of(vertices)
    brush = Brush("mask", radius=0.08, strength=0.7)
    sculptor.apply_brush(brush, [BrushEvent(top, [0.1, 0.0, 0.0], amount=0.6)])
    sculptor.apply_brush(brush, [BrushEvent(top, [0.0, 0.1, 0.0], amount=-0.3)])  # erase
    sculptor.apply_brush(Brush("grab", radius=0.15), [an_event(vertices)])
    sculptor.mask.invert()
    sculptor.apply_brush(Brush("smooth", radius=0.15), [an_event(vertices)])
    sculptor.undo()
    sculptor.redo()
    sculptor.mask.clear()
    sculptor.undo()
    session = json.loads(json.dumps(sculptor.session()))
    names = [op["op"] for op in session["operations"]]
    assert {"mask_invert", "mask_clear", "undo", "redo"} <= set(names)
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.mask.values, sculptor.mask.values)
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert again.history.undo_labels == sculptor.history.undo_labels
    assert again.session() == session


def test_a_failed_replay_rolls_the_mask_back(sphere):
    sculptor = masked(sphere)
    painted = sculptor.mask.values.copy()
    bad = [{"op": "mask_invert"}, {"op": "constraint_remove", "index": 3}]
    with pytest.raises(ValueError, match="operations\\[1\\]"):
        sculptor.replay(bad)
    assert np.array_equal(sculptor.mask.values, painted)
    assert sculptor.history.undo_labels == ["Mask stroke"]


def test_a_cancelled_mask_stroke_puts_the_mask_back(sphere):
    vertices, _faces = sphere
    sculptor = masked(sphere)
    painted = sculptor.mask.values.copy()
    sculptor.begin_stroke(Brush("mask", radius=0.3))
    sculptor.stroke_event(BrushEvent(-top_of(vertices), amount=1.0))
    assert not np.array_equal(sculptor.mask.values, painted)
    with pytest.raises(RuntimeError, match="invert the mask during a stroke"):
        sculptor.mask.invert()
    sculptor.cancel_stroke()
    assert np.array_equal(sculptor.mask.values, painted)


def test_the_tools_paint_a_dab_at_the_press_and_ctrl_erases(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    brush = Brush("mask", radius=0.1)
    tools = SculptTools(sculptor, brush=lambda: brush)
    top = top_of(vertices)
    update = tools.press(PointerEvent((100.0, 100.0), top, top))
    assert update.moved is not None and len(update.moved)  # the dab
    assert sculptor.mask.values.max() == 1.0
    tools.move(PointerEvent((110.0, 100.0), top + np.array([0.05, 0.0, 0.0])))
    tools.flush()
    assert tools.release().note is None  # recorded: no "nothing changed" though no vertex moved
    painted = sculptor.mask.values.copy()
    assert sculptor.history.undo_labels == ["Mask stroke"]
    ctrl = frozenset({"ctrl"})
    tools.press(PointerEvent((100.0, 100.0), top, top, modifiers=ctrl))
    tools.release()
    assert sculptor.mask.values.sum() < painted.sum()
    assert np.array_equal(sculptor.vertices, vertices)
