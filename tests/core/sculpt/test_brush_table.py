"""The brush table and its interface: rows by kind, results the stroke driver writes."""

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import (
    AFFINE_BRUSHES,
    BRUSH_KINDS,
    BRUSH_ROWS,
    BRUSH_TABLE,
    DRAGS,
    GRAB_BRUSHES,
    PAINT_BRUSHES,
    GreenBrush,
    StrokeContext,
    brush_type,
)


def test_every_kind_is_one_row_in_key_order():
    assert BRUSH_KINDS == tuple(row.kind for row in BRUSH_TABLE)
    assert len(set(BRUSH_KINDS)) == len(BRUSH_KINDS)
    assert BRUSH_KINDS[:5] == GRAB_BRUSHES and BRUSH_KINDS[5:9] == AFFINE_BRUSHES
    assert BRUSH_KINDS[9:] == PAINT_BRUSHES
    assert set(BRUSH_KINDS) == {*GRAB_BRUSHES, *AFFINE_BRUSHES, *PAINT_BRUSHES}
    for kind in BRUSH_KINDS:
        assert Brush(kind).type is brush_type(kind)
        assert Brush(kind).is_affine == (kind in AFFINE_BRUSHES)
    with pytest.raises(ValueError, match="unknown brush 'smudge'"):
        brush_type("smudge")


def test_rows_can_be_told_apart():
    for name in ("kind", "label", "letter", "icon"):
        values = [getattr(row, name) for row in BRUSH_ROWS]
        assert len(set(values)) == len(values), name
    numbers = [row.number for row in BRUSH_ROWS if row.number]
    assert len(set(numbers)) == len(numbers) and set(numbers) <= set("1234567890")
    assert {row.drag for row in BRUSH_ROWS} <= set(DRAGS)


@pytest.mark.parametrize("kind", [row.kind for row in BRUSH_TABLE if isinstance(row, GreenBrush)])
def test_a_green_brush_gives_the_same_rows_written_through_or_not(kind):
    """The driver may let a brush write its rows itself (nothing to apply on the way) or
    write them itself (a mask would): the same positions either way, bit for bit."""
    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces)
    brush = Brush(kind, radius=0.15)
    event = BrushEvent(vertices[7], [0.0, 0.02, 0.01], amount=0.1, axis=vertices[7])
    row = brush.type
    assert isinstance(row, GreenBrush)
    context = sculptor._strokes.context(sculptor._kernels)
    held = StrokeContext(context.mesh, context.kernels, context.rows, write_through=False)
    kept = row.displace(held, brush, event)
    assert not kept.written and np.array_equal(sculptor.vertices, vertices)  # not written
    rows, positions = kept.rows.copy(), kept.positions.copy()
    assert len(rows) and np.any(positions != vertices[rows])
    written = row.displace(context, brush, event)
    assert written.written and np.array_equal(written.rows, rows)
    assert np.array_equal(sculptor.vertices[rows], positions)
    # the driver's own stroke gives the same
    fresh = Sculptor(vertices, faces)
    fresh.apply_brush(brush, [event])
    assert np.array_equal(fresh.vertices, sculptor.vertices)
