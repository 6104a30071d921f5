"""Radial profiles (falloffs): closed forms, tables, and the editable spline profile."""

import functools
import json

import numpy as np
import pytest
from scipy import special

from gogreen_core import GaussianRadial, GreenKernel, KelvinletRadial, Material, SplineRadial
from gogreen_core.physics.radial import radial_from_dict
from gogreen_core.physics.radial_tables import radial_table


@functools.cache
def _gauss_legendre_0_60() -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(3000)
    return 30 * (x + 1), 30 * w


def radial_quadrature(ghat, l: int, r: float, power: int) -> float:
    """∫₀^∞ ĝ(k) j_l(kr) k^power dk by dense Gauss–Legendre on [0, 60] (ε = 1)."""
    k, w = _gauss_legendre_0_60()
    return float(np.sum(w * ghat(k) * special.spherical_jn(l, k * r) * k**power))


def kelvinlet_ghat(k):
    out = np.ones_like(k)
    nz = k > 0
    out[nz] = k[nz] ** 2 * special.kv(2, k[nz]) / 2
    return out


@pytest.mark.parametrize(
    ("profile", "ghat"),
    [(GaussianRadial(1.0), lambda k: np.exp(-(k**2) / 4)), (KelvinletRadial(1.0), kelvinlet_ghat)],
)
@pytest.mark.parametrize("l", [0, 1, 2, 5, 8, 13])
def test_closed_forms_match_radial_integrals(profile, ghat, l):
    for r in (0.3, 1.0, 3.0, 7.0):
        if l % 2 == 0:
            value, reference = profile.dimensionless("R", l, r), radial_quadrature(ghat, l, r, 0)
        else:
            value, reference = profile.dimensionless("dR", l, r), radial_quadrature(ghat, l, r, 1)
        assert abs(value - reference) < 1e-10 * max(abs(reference), 1e-3)


def test_kelvinlet_transform_is_normalized():
    # ĝ(0) = 1 ⇔ ∫ g = 1: the far field of R_0 is the singular one, (π/2)/r.
    assert np.isclose(KelvinletRadial(1.0).dimensionless("R", 0, 1e6) * 1e6, np.pi / 2, rtol=1e-9)


@pytest.mark.parametrize("profile", [GaussianRadial(1.0), KelvinletRadial(1.0)])
def test_tables_reproduce_profiles(profile):
    rho = np.concatenate([np.linspace(0, 3, 301), np.geomspace(3, 1e5, 200)])
    t = rho / (1 + rho)
    for kind, l in (("R", 0), ("R", 8), ("dR", 1), ("dR", 9), ("R", 20)):
        table = radial_table(profile, kind, l)
        u = t * table.shape[0]
        j = np.minimum(u.astype(int), table.shape[0] - 1)
        s = 2 * (u - j) - 1
        value = np.polynomial.polynomial.polyval(s, table[j].T, tensor=False)
        exact = profile.dimensionless(kind, l, rho) * (1 + rho) ** (1 if kind == "R" else 2)
        # Kelvinlet tails carry log terms near t = 1 that the polynomials resolve less well.
        tol = 1e-13 if isinstance(profile, GaussianRadial) else 1e-9
        assert np.abs(value - exact).max() < tol * np.abs(exact).max()


def test_spline_sampled_from_gaussian_approximates_it():
    spline = SplineRadial.from_profile(GaussianRadial(0.4), l_max=8)
    material = Material.cubic(3.0, 1.5, 0.4)
    x = np.random.default_rng(0).normal(size=(100, 3)) * 0.4
    exact = GreenKernel(material, l_max=8, radial=GaussianRadial(0.4)).green(x)
    approx = GreenKernel(material, l_max=8, radial=spline).green(x)
    assert np.abs(approx - exact).max() < 2e-2 * np.abs(exact).max()


def test_spline_keeps_zero_at_origin_and_edits_change_the_kernel():
    spline = SplineRadial.from_profile(GaussianRadial(1.0), l_max=4)
    rho, value = spline.curve("R", 2)
    spline = spline.with_curves({("R", 2): (rho, value + 0.5)})
    assert spline.curve("R", 2)[1][0] == 0.0  # pinned for l >= 1
    assert spline.dimensionless("dR", 1, np.array([0.0]))[0] == 0.0
    material = Material.cubic(3.0, 1.5, 0.4)
    x = np.array([[0.3, 0.2, 0.1]])
    before = GreenKernel(material, l_max=4, radial=spline).green(x)
    version = spline.version
    spline = spline.with_point_moved("R", 0, 2, float(rho[2]), 2.0)
    assert spline.version == version + 1
    after = GreenKernel(material, l_max=4, radial=spline).green(x)
    assert not np.allclose(before, after)
    spline, index = spline.with_point_added("R", 0, 0.6, 1.0)
    assert spline.curve("R", 0)[0][index] == 0.6
    spline = spline.without_point("R", 0, index)
    with pytest.raises(ValueError, match="rho = 0"):
        spline.without_point("R", 0, 0)


def test_spline_json_round_trip_and_far_field():
    spline = SplineRadial.from_profile(KelvinletRadial(0.7), l_max=6)
    again = radial_from_dict(json.loads(json.dumps(spline.to_dict())))
    assert again.eps == spline.eps
    rho = np.linspace(0, 30, 50)
    for kind, l in spline.curve_keys():
        assert np.array_equal(again.dimensionless(kind, l, rho), spline.dimensionless(kind, l, rho))
    data = json.loads(json.dumps(spline.to_dict()))
    assert data["type"] == "spline" and len(data["curves"]) == 8  # R_0,2,4,6 and ℛ_1,3,5,7
    tail = spline.dimensionless("R", 0, np.array([20.0, 40.0]))
    assert np.isclose(tail[0], 2 * tail[1])  # 1/ρ decay beyond the last control point


def test_profiles_round_trip_through_dict():
    for profile in (GaussianRadial(0.3), KelvinletRadial(2.0)):
        assert radial_from_dict(profile.to_dict()) == profile


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: SplineRadial(1.0, {("R", 0): ([0.1, 1, 2], [1, 1, 1])}), "rho = 0"),
        (lambda: SplineRadial(1.0, {("R", 0): ([0, 2, 1], [1, 1, 1])}), "increasing"),
        (lambda: SplineRadial(1.0, {("R", 0): ([0, 1], [1, 1])}), "at least 3"),
        (lambda: SplineRadial(1.0, {("R", 0): ([0, 1, 2], [1, np.nan, 1])}), "finite"),
        (lambda: SplineRadial(0.0, {("R", 0): ([0, 1, 2], [1, 1, 1])}), "eps"),
        (lambda: SplineRadial(1.0, {("Q", 0): ([0, 1, 2], [1, 1, 1])}), "kind"),
        (lambda: radial_from_dict({"type": "cauchy", "eps": 1.0}), "unknown falloff"),
        (
            lambda: GreenKernel(
                Material.cubic(3, 1.5, 0.4),
                l_max=8,
                radial=SplineRadial.from_profile(GaussianRadial(1.0), l_max=4),
            ),
            "no curve",
        ),
    ],
)
def test_bad_profiles_raise_value_error(build, message):
    with pytest.raises(ValueError) as info:
        build()
    assert message in str(info.value)


def test_quadrature_helper_is_accurate():
    # Guard the test's own reference: ∫₀^∞ e^{-k²/4} j_0(k) dk = (π/2) erf(1).
    value = radial_quadrature(lambda k: np.exp(-(k**2) / 4), 0, 1.0, 0)
    assert np.isclose(value, np.pi / 2 * special.erf(1.0), rtol=1e-12)


def test_spline_tables_follow_content_not_object_identity():
    """Falloffs built and dropped in a loop (so CPython reuses their ids, at edit count 0) each
    get the table of their own curves, and equal curves share one table."""
    base = SplineRadial.from_profile(GaussianRadial(1.0), 2)
    for i in range(40):
        rho, value = base.curve("R", 0)
        profile = SplineRadial(1.0, {("R", 0): (rho, value * (1.0 + 0.1 * i))})
        cached = profile.table("R", [0])[0]
        np.testing.assert_array_equal(cached, radial_table(profile, "R", 0))
        del profile
    twin = radial_from_dict(json.loads(json.dumps(base.to_dict())))
    assert twin.table_key() == base.table_key()
    np.testing.assert_array_equal(twin.table("R", [2]), base.table("R", [2]))
    twin = twin.with_point_moved("R", 2, 3, *twin.curve("R", 2)[0][3:4], 0.5)
    assert twin.table_key() != base.table_key()
    np.testing.assert_array_equal(twin.table("R", [2])[0], radial_table(twin, "R", 2))


def test_spline_control_points_follow_the_mesh_resolution():
    """A spline made for a mesh has a control point every two edges up to ρ = 4 (every 0.25
    at least, every 1/16 at most), so its smallest editable scale is what the mesh shows."""
    from gogreen_core.mesh.resolution import mean_edge_length, spline_abscissae
    from gogreen_core.mesh.shapes import icosphere
    from gogreen_core.physics.radial import DEFAULT_SPLINE_RHO

    assert np.array_equal(spline_abscissae(), DEFAULT_SPLINE_RHO)
    fine = spline_abscissae(14.0)  # ε spans 14 edges: a point every 1/7
    assert fine[0] == 0 and np.allclose(np.diff(fine[:29]), 1 / 7) and fine[28] == 4.0
    assert list(fine[29:]) == [5.0, 6.0, 8.0, 10.0]
    assert len(spline_abscissae(4.0)) == 21  # coarse: every 0.25
    assert len(spline_abscissae(1e6)) == 69  # capped at 1/16
    with pytest.raises(ValueError, match="edges_per_eps"):
        spline_abscissae(0.0)
    vertices, faces = icosphere(3)
    edge = mean_edge_length(vertices, faces)
    assert 0.1 < edge < 0.2  # unit sphere, 642 vertices
    spline = SplineRadial.from_profile(GaussianRadial(1.0), 4, spline_abscissae(0.5 / edge))
    assert len(spline.curve("R", 0)[0]) == len(spline_abscissae(0.5 / edge))
