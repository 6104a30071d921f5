"""Spline falloffs without overshoot: the monotone interpolant of new curves, the cubic spline
of saved ones (bit for bit), and the rim striations the cubic's ringing made."""

import json
import sys

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.field.kernel import GreenKernel
from gogreen_core.interaction.tools import grab_motion
from gogreen_core.physics.radial import (
    DEFAULT_SPLINE_RHO,
    GaussianRadial,
    SplineRadial,
    local_slopes,
    monotone_hermite,
)
from gogreen_core.sculpt.schema import parse_falloff
from gogreen_core.validation import ParameterError

RHO = DEFAULT_SPLINE_RHO


def extrema(values, x):
    """Where ``values`` (sampled at ``x``) turn."""
    step = np.diff(values)
    turns = np.flatnonzero(np.sign(step[1:]) * np.sign(step[:-1]) < 0) + 1
    return x[turns]


def raised(interpolation, amount=0.3):
    """The default falloff and the issue's edit of it: R₀ at ρ = 2 raised by ``amount``."""
    spline = SplineRadial.from_profile(GaussianRadial(1.0), 8, interpolation=interpolation)
    spline = spline.as_value()
    rho, value = spline.curve("R", 0)
    index = int(np.flatnonzero(rho == 2.0)[0])
    return spline, spline.with_point_moved("R", 0, index, 2.0, value[index] + amount)


def test_monotone_between_control_points_under_any_single_edit():
    rng = np.random.default_rng(7)
    x = np.linspace(0, 1, 4001)
    for _trial in range(200):
        rho = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1.0, 9))])
        value = rng.normal(size=10)
        curve = monotone_hermite(rho, value)
        np.testing.assert_allclose(curve(rho), value, rtol=0, atol=1e-14)  # through its points
        for a, b, ya, yb in zip(rho[:-1], rho[1:], value[:-1], value[1:], strict=True):
            inside = curve(a + (b - a) * x)
            low, high = min(ya, yb), max(ya, yb)
            assert inside.min() >= low - 1e-12 and inside.max() <= high + 1e-12
        # moving one point changes the curve around the points whose slope stencil holds it
        # (its third neighbours away from the ends: ρ = 2 of the default curves, below)
        i = int(rng.integers(0, 10))
        moved = value.copy()
        moved[i] += rng.normal()
        other = monotone_hermite(rho, moved)
        starts = np.clip(np.arange(10) - 2, 0, 5)  # each point's five-point stencil
        touched = np.flatnonzero((starts <= i) & (i < starts + 5))
        first, last = max(touched.min() - 1, 0), min(touched.max() + 1, 9)
        for a, b in ((0, first), (last, 9)):
            if a == b:
                continue  # the edited point at an end
            stretch = np.linspace(rho[a], rho[b], 50)
            assert np.array_equal(curve(stretch), other(stretch))


def test_local_slopes_are_fourth_order():
    rho = np.array([0.0, 0.3, 0.5, 1.1, 1.2, 2.0])
    quartic = np.poly1d([0.5, -1.0, 2.0, 3.0, -1.0])
    np.testing.assert_allclose(local_slopes(rho, quartic(rho)), quartic.deriv()(rho), atol=1e-12)


def _python_calls(fn, *args):
    """How many Python and C functions ``fn(*args)`` calls (sys.setprofile events)."""
    calls = 0

    def count(frame, event, arg):
        nonlocal calls
        calls += event in ("call", "c_call")

    sys.setprofile(count)
    try:
        fn(*args)
    finally:
        sys.setprofile(None)
    return calls


def test_local_slopes_do_not_loop_in_python_per_point():
    """A falloff reset rebuilds 30 curves on the GUI thread (issue 32: the per-point Lagrange
    loops took 0.4 s under load): the slopes cost the same number of calls at 10 or 200
    points."""
    few = np.linspace(0.0, 6.0, 10)
    many = np.linspace(0.0, 6.0, 200)
    assert _python_calls(local_slopes, many, np.exp(-0.5 * many**2)) == _python_calls(
        local_slopes, few, np.exp(-0.5 * few**2)
    )


@pytest.mark.parametrize("n", [3, 4, 5, 6, 9, 25])
def test_local_slopes_are_the_lagrange_slopes_of_each_stencil(n):
    """Each point's slope is the derivative there of the polynomial through its stencil (an
    exact polynomial fit of the same points), within 1e-12 relative."""
    rng = np.random.default_rng(n)
    rho = np.sort(rng.uniform(0.0, 8.0, n)) + np.arange(n) * 0.05
    value = np.exp(-0.5 * rho**2) + rng.normal(0.0, 0.1, n)
    width = min(5, n)
    expected = []
    for i in range(n):
        start = min(max(i - 2, 0), n - width)
        x, y = rho[start : start + width], value[start : start + width]
        fit = np.polynomial.Polynomial.fit(x, y, width - 1)
        expected.append(fit.deriv()(rho[i]))
    got = local_slopes(rho, value)
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10 * scale)


def test_the_issues_edit_dips_with_the_cubic_and_not_with_the_monotone_curve():
    x = np.linspace(0.0, 6.0, 60001)
    cubic_before, cubic_after = raised("cubic")
    monotone_before, monotone_after = raised("monotone")
    # the cubic: new minima near 1.7 and 2.8 (the issue saw 1.8 and 2.6) and a ringing maximum
    turns = extrema(cubic_after.dimensionless("R", 0, x), x)
    assert np.any(np.abs(turns - 1.72) < 0.02) and np.any(np.abs(turns - 2.80) < 0.02)
    assert np.any(np.abs(turns - 3.01) < 0.02)
    # the monotone curve turns at the moved point and its neighbour, nowhere else
    np.testing.assert_allclose(extrema(monotone_after.dimensionless("R", 0, x), x), [1.75, 2.0])
    # and the edit changes nothing beyond the third neighbour (ρ = 3.5)
    far = x[x >= 3.5]
    assert np.array_equal(
        monotone_after.dimensionless("R", 0, far), monotone_before.dimensionless("R", 0, far)
    )
    change = cubic_after.dimensionless("R", 0, far) - cubic_before.dimensionless("R", 0, far)
    assert np.abs(change).max() > 1e-3  # the cubic's ringing reaches every interval


def test_the_default_curves_are_as_close_to_the_gaussian_as_the_cubic_ones():
    x = np.linspace(0.05, 5.0, 5000)
    for kind, l in [("R", 0), ("R", 2), ("dR", 1), ("dR", 3)]:
        exact = GaussianRadial(1.0).dimensionless(kind, l, x)
        errors = {}
        for interpolation in ("cubic", "monotone"):
            spline = SplineRadial.from_profile(GaussianRadial(1.0), 8, interpolation=interpolation)
            errors[interpolation] = np.abs(spline.dimensionless(kind, l, x) - exact).max()
        assert errors["monotone"] < 2.0 * errors["cubic"], (kind, l, errors)


def test_event_fields_have_rings_only_where_the_artist_moved_a_point():
    """The striations along a stroke's rim are the rings of each event's field swept along
    the path: the cubic's edit gives the field extra rings (its dips and its ringing), the
    monotone curve's field turns only at the edited control points."""
    material = Material.isotropic(1.0, 0.3)
    r = np.linspace(0.0, 4.0, 8001)
    rings = {}
    for interpolation in ("cubic", "monotone"):
        before, after = raised(interpolation)
        rings[interpolation] = [
            extrema(grab_motion(GreenKernel(material, 8, f), r), r) for f in (before, after)
        ]
    assert len(rings["monotone"][0]) == 0  # the default field falls monotonically
    np.testing.assert_allclose(rings["monotone"][1], [1.75, 2.0], atol=1e-3)
    assert len(rings["cubic"][1]) >= 4  # 1.72, 2.04, 2.80, 3.01 (and a wiggle at the centre)
    assert np.any(rings["cubic"][1] > 2.5)


def test_a_strokes_rim_beyond_the_edit_is_untouched_by_it():
    """Vertices more than 3.6 ε from the stroke path move as without the edit with the
    monotone curve, to the integrator's tolerance (its choice of steps is made for the whole
    event: third-order ones where probes anywhere show them enough); with the cubic the edit's
    ringing moves them differently, two orders of magnitude more."""
    n = 121
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    vertices = np.stack([x.ravel(), y.ravel(), np.zeros(n * n)], axis=1)
    index = np.arange(n * n).reshape(n, n)
    quads = np.stack(
        [index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]], axis=-1
    ).reshape(-1, 4)
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    brush = Brush("grab", radius=0.05)
    path = np.linspace(-0.3, 0.3, 13)
    events = [BrushEvent([a, 0.0, 0.01 * k], [path[1] - path[0], 0.0, 0.01]) for k, a in
              enumerate(path[:-1])]  # fmt: skip
    moved = {}
    for interpolation in ("cubic", "monotone"):
        for name, falloff in zip(("before", "after"), raised(interpolation), strict=True):
            sculptor = Sculptor(vertices, faces, falloff=falloff)
            sculptor.apply_brush(brush, events)
            moved[interpolation, name] = sculptor.vertices.copy()
    eps = 0.05 * np.sqrt(8.0)
    gap = np.maximum(np.abs(vertices[:, 0]) - 0.3, 0.0)
    far = np.hypot(gap, vertices[:, 1]) > 3.6 * eps
    reached = np.any(moved["monotone", "before"] != vertices, axis=1)
    assert np.any(far & reached)  # the rim reaches beyond 3.6 ε (influence 4 ε)
    motion = np.linalg.norm(events[0].delta)
    for interpolation, low, high in (("monotone", 0.0, 1e-4), ("cubic", 1e-3, np.inf)):
        after, before = moved[interpolation, "after"][far], moved[interpolation, "before"][far]
        assert low <= np.abs(after - before).max() / motion < high, interpolation


def test_saved_cubic_falloffs_still_read_and_write_as_before():
    curves = {("R", 0): (RHO, GaussianRadial(1.0).dimensionless("R", 0, RHO))}
    old = {
        "type": "spline",
        "eps": 1.0,
        "curves": [{"kind": "R", "degree": 0, "rho": RHO.tolist(), "value": curves["R", 0][1]}],
    }
    old["curves"][0]["value"] = old["curves"][0]["value"].tolist()
    spline = parse_falloff(json.loads(json.dumps(old)))
    assert spline.interpolation == "cubic"
    assert spline.to_dict() == old  # no "interpolation" written for the cubic
    x = np.linspace(0.0, 10.0, 1001)
    assert np.array_equal(spline.dimensionless("R", 0, x), CubicSpline(*curves["R", 0])(x))
    new = SplineRadial.from_profile(GaussianRadial(1.0), 2)
    assert new.interpolation == "monotone" and new.to_dict()["interpolation"] == "monotone"
    again = parse_falloff(json.loads(json.dumps(new.to_dict())))
    assert again == new and again != new.with_interpolation("cubic")
    assert again.table_key() != new.with_interpolation("cubic").table_key()
    with pytest.raises(ParameterError, match=r"falloff\.interpolation"):
        parse_falloff({**new.to_dict(), "interpolation": "akima"})


@pytest.mark.parametrize("interpolation", ["cubic", "monotone"])
def test_sessions_replay_their_own_interpolation_bit_for_bit(interpolation):
    from gogreen_core.mesh.shapes import icosphere

    vertices, faces = icosphere(3)
    before, after = raised(interpolation)
    sculptor = Sculptor(vertices, faces, falloff=before)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.change_settings(falloff=after)
    sculptor.apply_brush(Brush("grab", radius=0.1), [BrushEvent(top, [0.0, 0.05, 0.05])])
    session = json.loads(json.dumps(sculptor.session()))
    assert ("interpolation" in json.dumps(session)) == (interpolation != "cubic")
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(session["operations"])
    assert np.array_equal(again.vertices, sculptor.vertices)
    assert again.settings.falloff.interpolation == interpolation
