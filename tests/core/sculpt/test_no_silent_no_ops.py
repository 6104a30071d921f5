"""No call silently does nothing (issue 37 item 4, issue 33 item 7): a paint event without an
amount acts at full pressure and is recorded so that a replay acts the same; an event that
cannot act without one and a stroke without events are refused, naming what is wrong."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.validation import ParameterError


@pytest.fixture(scope="module")
def bumpy():
    vertices, faces = icosphere(3)
    rng = np.random.default_rng(5)
    return vertices * (1.0 + 0.03 * rng.standard_normal(len(vertices)))[:, None], faces


def top(vertices: np.ndarray) -> np.ndarray:
    return vertices[int(np.argmax(vertices[:, 2]))].copy()


def replayed(sculptor: Sculptor, vertices: np.ndarray, faces: np.ndarray) -> Sculptor:
    session = json.loads(json.dumps(sculptor.session()))
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    return again


def test_a_smooth_event_without_amount_smooths_at_full_pressure_and_replays(bumpy):
    vertices, faces = bumpy
    without = Sculptor(vertices, faces)
    moved = without.apply_brush(Brush("smooth", radius=0.3), [BrushEvent(top(vertices))] * 3)
    assert len(moved) > 0
    full = Sculptor(vertices, faces)
    full.apply_brush(Brush("smooth", radius=0.3), [BrushEvent(top(vertices), amount=1.0)] * 3)
    assert np.array_equal(without.vertices, full.vertices)
    (stroke,) = without.session()["operations"]
    assert [event["amount"] for event in stroke["events"]] == [1.0, 1.0, 1.0]
    assert np.array_equal(replayed(without, vertices, faces).vertices, without.vertices)
    # Pressure 0 (a pen touching down) is an amount given: it smooths nothing, as it says; and
    # a file leaves a zero amount out (to_dict), so absent in a file still reads as 0.
    zero = Sculptor(vertices, faces)
    assert len(zero.apply_brush(Brush("smooth"), [BrushEvent(top(vertices), amount=0)])) == 0
    assert BrushEvent.from_dict({"center": [0, 0, 0]}).amount == 0.0


def test_a_mask_event_without_amount_paints_at_full_pressure_and_replays(bumpy):
    vertices, faces = bumpy
    sculptor = Sculptor(vertices, faces)
    sculptor.apply_brush(Brush("mask", radius=0.3), [BrushEvent(top(vertices))])
    mask = sculptor.mask.values.copy()
    assert mask.max() == 1.0  # full pressure at the centre
    (stroke,) = sculptor.session()["operations"]
    assert stroke["events"][0]["amount"] == 1.0
    again = replayed(sculptor, vertices, faces)
    assert np.array_equal(again.mask.values, mask)


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_an_affine_event_without_amount_is_refused_naming_it(bumpy, kind):
    vertices, faces = bumpy
    sculptor = Sculptor(vertices, faces)
    with pytest.raises(ParameterError, match=r"amount") as caught:
        sculptor.apply_brush(Brush(kind, radius=0.3), [BrushEvent(top(vertices))])
    assert caught.value.parameter.endswith("amount")
    assert np.array_equal(sculptor.vertices, vertices)  # nothing moved


def test_a_stroke_without_events_is_refused(bumpy):
    vertices, faces = bumpy
    sculptor = Sculptor(vertices, faces)
    with pytest.raises(ParameterError, match="at least one event") as caught:
        sculptor.apply_brush(Brush("grab", radius=0.3), [])
    assert caught.value.parameter == "events"
    assert not sculptor.in_stroke
