"""GreenKernel against independent references, its symmetries, and its input checks."""

import itertools
import os
import subprocess
import sys

import numpy as np
import pytest
from green_reference import backus_laminate, kelvinlet_closed_form, reference_green

from gogreen_core import GaussianRadial, GreenKernel, KelvinletRadial, Material
from gogreen_core._compiled import forced
from gogreen_core.field.kernel import COORDINATE_LIMIT
from gogreen_core.validation import ParameterError

EPS = 0.5


def random_rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def random_spd_material(seed: int) -> Material:
    a = np.random.default_rng(seed).normal(size=(6, 6))
    return Material.from_voigt(a @ a.T + 2 * np.eye(6))


MATERIALS = {
    "isotropic": Material.isotropic(2.6, 0.3),
    "cubic": Material.cubic(3.0, 1.5, 0.4),
    "laminate": Material.from_voigt(backus_laminate()).rotated(random_rotation(7)),
    "general21": random_spd_material(3),
}


def sample_offsets(n: int, seed: int, max_radius: float = 6 * EPS) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(n, 3))
    return x * (rng.uniform(0.02, 1, n) * max_radius / np.linalg.norm(x, axis=1))[:, None]


@pytest.fixture(scope="module")
def references():
    out = {}
    for name, material in MATERIALS.items():
        x = sample_offsets(10, seed=len(name))
        pairs = [reference_green(material, p, EPS) for p in x]
        out[name] = (x, np.array([g for g, _ in pairs]), np.array([d for _, d in pairs]))
    return out


def rel_err(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


# (material, l_max) -> tolerance on G and ∇G relative error: the SH truncation error measured
# against the plane-wave reference, with margin (see ../shared/MATH.md for the figures).
TOLERANCES = {
    ("isotropic", 2): (1e-10, 1e-10),
    ("isotropic", 8): (1e-10, 1e-10),
    ("cubic", 8): (4e-4, 1e-3),
    ("cubic", 20): (1e-8, 5e-8),
    ("laminate", 8): (3e-3, 1e-2),
    ("laminate", 20): (2e-5, 2e-4),
    ("general21", 8): (1e-3, 3e-3),
    ("general21", 20): (1e-6, 1e-5),
}


@pytest.mark.parametrize(("name", "l_max"), list(TOLERANCES))
def test_green_and_gradient_match_plane_wave_reference(references, name, l_max):
    x, g_ref, dg_ref = references[name]
    kernel = GreenKernel(MATERIALS[name], l_max=l_max, radial=GaussianRadial(EPS))
    tol_g, tol_dg = TOLERANCES[(name, l_max)]
    assert rel_err(kernel.green(x), g_ref) < tol_g
    assert rel_err(kernel.green_gradient(x), dg_ref) < tol_dg


@pytest.mark.parametrize("name", ["cubic", "laminate"])
def test_error_decreases_with_l_max(references, name):
    x, g_ref, _dg_ref = references[name]
    errors = [
        rel_err(GreenKernel(MATERIALS[name], l_max=l, radial=GaussianRadial(EPS)).green(x), g_ref)
        for l in (2, 6, 10, 16, 24)
    ]
    assert all(b < a for a, b in itertools.pairwise(errors)), errors
    assert errors[-1] < 1e-3 * errors[0]


def test_kelvinlet_profile_reproduces_closed_form_kelvinlets():
    mu, nu = 0.8, 0.32
    material = Material.isotropic(2 * mu * (1 + nu), nu)
    x = sample_offsets(400, seed=5, max_radius=20 * EPS)
    x[0] = 0.0
    g_ref, dg_ref = kelvinlet_closed_form(x, EPS, mu, nu)
    for l_max in (2, 8):
        kernel = GreenKernel(material, l_max=l_max, radial=KelvinletRadial(EPS))
        assert rel_err(kernel.green(x), g_ref) < 1e-10
        assert rel_err(kernel.green_gradient(x), dg_ref) < 1e-10
        force = np.array([0.3, -1.2, 0.7])
        center = np.array([0.1, 0.2, -0.3])
        u = kernel.displacement(x + center, center, force)
        assert rel_err(u, g_ref @ force) < 1e-10
        load = np.array([[0.2, 1.0, -0.4], [0.5, -0.3, 0.8], [0.1, 0.9, 0.6]])
        u_aff = kernel.affine_displacement(x + center, center, load)
        assert rel_err(u_aff, np.einsum("nijp,jp->ni", dg_ref, load)) < 1e-10


def test_kelvinlet_reference_for_anisotropic_material():
    material = MATERIALS["cubic"]
    x = sample_offsets(6, seed=11)
    kernel = GreenKernel(material, l_max=20, radial=KelvinletRadial(EPS))
    for p in x:
        g_ref, dg_ref = reference_green(material, p, EPS, kind="kelvinlet")
        # The algebraic Kelvinlet load has a wider angular spectrum than the Gaussian one.
        assert rel_err(kernel.green(p[None])[0], g_ref) < 1e-6
        assert rel_err(kernel.green_gradient(p[None])[0], dg_ref) < 1e-5


def test_pde_residual_by_finite_differences():
    """C_ijkl ∂j∂l G_km + δ_im g_ε = 0 for a strongly anisotropic material (rotated laminate)."""
    material = MATERIALS["laminate"]
    kernel = GreenKernel(material, l_max=24, radial=GaussianRadial(EPS))
    c = material.tensor
    h = 2e-3 * EPS
    x = sample_offsets(8, seed=2, max_radius=1.5 * EPS)
    second = np.empty((len(x), 3, 3, 3, 3))  # [n, k, m, l, j] = ∂j ∂l G_km
    for j in range(3):
        step = np.zeros(3)
        step[j] = h
        d_plus, d_minus = kernel.green_gradient(x + step), kernel.green_gradient(x - step)
        second[..., j] = (d_plus - d_minus) / (2 * h)
    r2 = np.einsum("ni,ni->n", x, x)
    load = np.exp(-r2 / EPS**2) / (EPS**3 * np.pi**1.5)
    residual = np.einsum("ijkl,nkmlj->nim", c, second) + load[:, None, None] * np.eye(3)
    assert np.abs(residual).max() / load.max() < 1e-3


def test_symmetries():
    kernel = GreenKernel(MATERIALS["general21"], l_max=10, radial=GaussianRadial(EPS))
    x = sample_offsets(50, seed=4)
    g, dg = kernel.green(x), kernel.green_gradient(x)
    scale = np.abs(g).max()
    assert np.abs(g - g.transpose(0, 2, 1)).max() < 1e-13 * scale
    assert np.abs(kernel.green(-x) - g).max() < 1e-13 * scale
    assert np.abs(kernel.green_gradient(-x) + dg).max() < 1e-13 * np.abs(dg).max()


def test_rotation_covariance():
    material = MATERIALS["general21"]
    rot = random_rotation(9)
    x = sample_offsets(30, seed=8)
    k = GreenKernel(material, l_max=16, radial=GaussianRadial(EPS))
    k_rot = GreenKernel(material.rotated(rot), l_max=16, radial=GaussianRadial(EPS))
    g, g_rot = k.green(x), k_rot.green(x @ rot.T)
    expected = np.einsum("ai,nij,bj->nab", rot, g, rot)
    # Exact covariance holds for the full series; the truncated one is covariant to its
    # truncation error (rotation mixes m within each degree, not degrees).
    assert rel_err(g_rot, expected) < 1e-9
    dg_rot = k_rot.green_gradient(x @ rot.T)
    expected_dg = np.einsum("ai,bj,cp,nijp->nabc", rot, rot, rot, k.green_gradient(x))
    assert rel_err(dg_rot, expected_dg) < 1e-9


def test_origin_and_tiny_radius_are_exact_and_finite():
    kernel = GreenKernel(MATERIALS["laminate"], l_max=12, radial=GaussianRadial(EPS))
    direction = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    x = np.array([[0.0, 0.0, 0.0], 1e-12 * EPS * direction, 1e-6 * EPS * direction])
    g, dg = kernel.green(x), kernel.green_gradient(x)
    assert np.all(np.isfinite(g)) and np.all(np.isfinite(dg))
    assert np.array_equal(dg[0], np.zeros((3, 3, 3)))
    assert rel_err(g[1], g[0]) < 1e-12 and rel_err(g[2], g[0]) < 1e-9
    g0_ref, _ = reference_green(MATERIALS["laminate"], np.zeros(3), EPS)
    assert rel_err(g[0], g0_ref) < 1e-3  # G(0) depends on every degree: truncation level


@pytest.mark.parametrize("l_max", [0, 1, 2, 5, 8, 12, 13, 16])
def test_loads_agree_with_green_and_gradient(l_max):
    # Vector and affine loads run the angular kernel generated for their degree (up to degree
    # 13) or the generic one; G and ∇G (9 and 27 outputs) always run the generic one.
    kernel = GreenKernel(MATERIALS["general21"], l_max=l_max, radial=GaussianRadial(EPS))
    with forced("unrolled"):  # the compiled code (NumPy's is within 1e-12 of it)
        assert kernel._even.backend().unrolled == (l_max <= 13)
        assert kernel._odd.backend().unrolled == (l_max <= 13)
        _check_loads_against_green(kernel)


def test_the_backend_is_chosen_once_it_is_final(monkeypatch):
    """NumPy while the compiled code is not ready; once it is (drivers and generated kernels),
    each parity keeps its backend and no call asks the compile driver again."""
    from gogreen_core import _compiled

    kernel = GreenKernel(MATERIALS["cubic"], l_max=6, radial=GaussianRadial(EPS))
    x = sample_offsets(50, seed=3)
    with forced("numpy"):
        assert not kernel._even.backend().compiled
        assert kernel._even._backend is None  # not final: asked again at the next call
    with forced("unrolled"):
        kernel.displacement(x, np.zeros(3), np.ones(3))  # compiled and loaded
    first = kernel._even.backend()
    assert first.compiled and first.unrolled and first.unrolled32
    assert kernel._even._backend is first

    def asked(*args):
        raise AssertionError("the backend was chosen again")

    monkeypatch.setattr(_compiled, "drivers", asked)
    kernel.displacement(x, np.zeros(3), np.ones(3))
    kernel.streamlines(x, np.zeros(3), np.ones(3), cutoff=(0.5, 1.0))
    assert kernel._even.backend() is first


def _check_loads_against_green(kernel):
    center = np.array([0.2, -0.1, 0.4])
    x = np.vstack([np.zeros(3), 1e-9 * np.ones(3), sample_offsets(300, seed=12), [[0, 0, 1e6]]])
    force = np.array([1.0, -2.0, 0.5])
    load = np.arange(9.0).reshape(3, 3) - 4
    vector = kernel.displacement(x + center, center, force)
    assert np.allclose(vector, kernel.green(x) @ force, rtol=1e-12, atol=1e-14 * abs(vector).max())
    expected = np.einsum("nijp,jp->ni", kernel.green_gradient(x), load)
    affine = kernel.affine_displacement(x + center, center, load)
    assert np.allclose(affine, expected, rtol=1e-12, atol=1e-14 * abs(expected).max())
    assert np.array_equal(affine[0], np.zeros(3))  # ∇G(0) = 0 exactly


def test_degree_weights_truncate_and_reweight():
    material = MATERIALS["cubic"]
    x = sample_offsets(40, seed=13)
    weights = np.zeros(13)
    weights[:5] = 1.0
    truncated = GreenKernel(material, l_max=12, degree_weights=weights)
    short = GreenKernel(material, l_max=4)
    assert rel_err(truncated.green(x), short.green(x)) < 1e-13
    assert rel_err(truncated.green_gradient(x), short.green_gradient(x)) < 1e-13
    doubled = GreenKernel(material, l_max=4, degree_weights=2 * np.ones(5))
    assert rel_err(doubled.green(x), 2 * short.green(x)) < 1e-13


def test_with_eps_and_l_max_range():
    material = MATERIALS["cubic"]
    kernel = GreenKernel(material, l_max=6, radial=GaussianRadial(1.0))
    x = sample_offsets(20, seed=14)
    # Scaling: G_ε(x) = G_1(x/ε)/ε.
    assert rel_err(kernel.with_eps(EPS).green(x), kernel.green(x / EPS) / EPS) < 1e-12
    for l_max in (0, 1, 30):
        k = GreenKernel(material, l_max=l_max)
        assert np.all(np.isfinite(k.green(x))) and np.all(np.isfinite(k.green_gradient(x)))


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: GreenKernel(MATERIALS["cubic"], l_max=-1), "l_max"),
        (lambda: GreenKernel(MATERIALS["cubic"], l_max=2.5), "integer"),
        (lambda: GreenKernel("steel"), "Material"),
        (lambda: GreenKernel(MATERIALS["cubic"], radial=0.5), "RadialProfile"),
        (lambda: GreenKernel(MATERIALS["cubic"], l_max=4, degree_weights=[1, 1]), "l_max + 1"),
        (lambda: GreenKernel(MATERIALS["cubic"], l_max=1, degree_weights=[1, np.nan]), "finite"),
        (lambda: GaussianRadial(0.0), "eps"),
        (lambda: GaussianRadial(-1.0), "eps"),
        (lambda: KelvinletRadial(float("nan")), "eps"),
        (lambda: GreenKernel(MATERIALS["cubic"]).green(np.zeros((3, 2))), "(N, 3)"),
        (lambda: GreenKernel(MATERIALS["cubic"]).green([[0.0, np.nan, 0.0]]), "non-finite"),
        (
            lambda: GreenKernel(MATERIALS["cubic"]).displacement(
                np.zeros((2, 3)), [0, 0], [1, 0, 0]
            ),
            "center",
        ),
        (
            lambda: GreenKernel(MATERIALS["cubic"]).displacement(
                np.zeros((2, 3)), [0, 0, 0], [1, np.inf, 0]
            ),
            "force",
        ),
        (
            lambda: GreenKernel(MATERIALS["cubic"]).affine_displacement(
                np.zeros((2, 3)), [0, 0, 0], np.eye(2)
            ),
            "affine load",
        ),
    ],
)
def test_bad_input_raises_value_error(build, message):
    with pytest.raises(ValueError) as info:
        build()
    assert message in str(info.value)


def test_the_full_sum_reaches_its_far_field_form_exponentially_only_at_degree_zero():
    """The full sum against its far-field form G(x̂ R) R (R = 1e8 ε; MATH.md): the degree-0
    term alone is there to rounding from 6 ε on (erfc), but the terms above it only
    algebraically (~l²/(4ρ²)): 1-2 % of G at 4 ε, where the streamlines' cutoff ends, 4e-4 at
    20 ε. A far-field shortcut of the brush field would miss the 1e-4 tolerance."""
    direction = np.array([[0.6, -0.48, 0.64]])

    def gap(kernel: GreenKernel, rho: float) -> float:
        far = kernel.green(direction * 1e8) * 1e8
        return float(np.abs(kernel.green(direction * rho) * rho - far).max() / np.abs(far).max())

    for material in (Material.isotropic(1.0, 0.3), Material.cubic(3.0, 1.5, 0.4)):
        alone = GreenKernel(material, l_max=0, radial=GaussianRadial(1.0))
        assert gap(alone, 4.0) < 1e-7 and gap(alone, 6.0) < 1e-14
        full = GreenKernel(material, l_max=8, radial=GaussianRadial(1.0))
        assert gap(full, 4.0) > 5e-3 and gap(full, 20.0) > 1e-4
        for rho in (6.0, 20.0):  # ρ² · gap settles to a constant
            assert 3.8 < gap(full, rho) / gap(full, 2 * rho) < 4.2


@pytest.mark.parametrize("radial", [GaussianRadial(0.3), KelvinletRadial(0.3)])
def test_far_points_decay_finitely(radial):
    """Points up to COORDINATE_LIMIT away give the far field, finite: r·u and r·G tend to a
    constant (r²·∇G too, until it underflows to 0); never NaN."""
    kernel = GreenKernel(MATERIALS["laminate"], l_max=8, radial=radial)
    direction = np.array([[0.6, -0.48, 0.64]])
    force, load = (
        np.array([0.3, -1.0, 0.2]),
        np.array([[0.1, 0.4, 0.0], [-0.4, 0.2, 0.1], [0, 0, 1]]),
    )
    near = 1e8
    u_far = kernel.displacement(direction * near, np.zeros(3), force) * near
    g_far = kernel.green(direction * near) * near
    d_far = kernel.green_gradient(direction * near) * near**2
    for r in (1e150, 1e160, 1e200, 1e250, COORDINATE_LIMIT / 2):
        center = np.array([-0.4, 0.2, 0.1]) * r  # the offset, not the coordinates, sets r
        points = direction * r + center
        u = kernel.displacement(points, center, force)
        np.testing.assert_allclose(u * r, u_far, rtol=1e-9)
        np.testing.assert_allclose(kernel.green(direction * r) * r, g_far, rtol=1e-9)
        affine = kernel.affine_displacement(points, center, load)
        gradient = kernel.green_gradient(direction * r)
        assert np.isfinite(affine).all() and np.isfinite(gradient).all()
        if r <= 1e150:  # r⁻² still a normal float
            np.testing.assert_allclose(gradient * r**2, d_far, rtol=1e-9, atol=1e-12)
        else:
            assert np.abs(gradient).max() <= 1e-290 and np.abs(affine).max() <= 1e-290
    # a point at a far distance next to ordinary ones: each gets its own value
    mixed = np.vstack([direction * 1e200, direction])
    u = kernel.displacement(mixed, np.zeros(3), force)
    np.testing.assert_array_equal(u[1:], kernel.displacement(direction, np.zeros(3), force))


@pytest.mark.parametrize(
    ("call", "parameter"),
    [
        (lambda k: k.displacement([[2e300, 0, 0]], np.zeros(3), np.ones(3)), "points"),
        (lambda k: k.displacement(np.zeros((1, 3)), [0, -1e301, 0], np.ones(3)), "center"),
        (lambda k: k.affine_displacement([[0, 0, 1e305]], np.zeros(3), np.eye(3)), "points"),
        (lambda k: k.affine_displacement(np.zeros((1, 3)), [1e308, 0, 0], np.eye(3)), "center"),
        (lambda k: k.green([[0, 0, -1.7e308]]), "offsets"),
        (lambda k: k.green_gradient([[1e301, 1e301, 0]]), "offsets"),
        (lambda k: k.displacement(np.zeros((1, 3)), np.zeros(3), [1e308, 1e308, 0]), "force"),
        (
            lambda k: k.affine_displacement(np.ones((1, 3)), np.zeros(3), np.eye(3) * 1e308),
            "affine load",
        ),
    ],
)
def test_beyond_the_coordinate_limit_raises_parameter_error(call, parameter):
    kernel = GreenKernel(Material.isotropic(1e-3, 0.3), l_max=4)
    with pytest.raises(ParameterError) as info:
        call(kernel)
    assert info.value.parameter == parameter and parameter in str(info.value)


def fibre_composite(seed: int = 11) -> tuple[Material, np.ndarray]:
    """Fibres at stiffness contrast 10⁴ (the homogenized effective tensor of round fibres,
    fraction ~0.3, in a matrix 10⁴ times softer), rotated off-axis; returns it and the fibre
    axis. M(ξ̂)⁻¹ has a ridge 0.016 rad wide around the great circle normal to the fibres."""
    voigt = np.zeros((6, 6))
    voigt[:3, :3] = [[2.357, 0.800, 0.947], [0.800, 2.357, 0.947], [0.947, 0.947, 2970.0]]
    voigt[3, 3] = voigt[4, 4] = 0.747
    voigt[5, 5] = 0.615
    rotation = random_rotation(seed)
    return Material.from_voigt(voigt).rotated(rotation), rotation[:, 2]


def axis_product_rule(axis: np.ndarray, n_u: int, n_phi: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre in u = ξ̂·axis × trapezoid in φ: a plain, fine product rule."""
    helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    u, wu = np.polynomial.legendre.leggauss(n_u)
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    sin_t = np.sqrt(1 - u**2)[:, None, None]
    dirs = u[:, None, None] * axis + sin_t * (
        np.cos(phi)[None, :, None] * e1 + np.sin(phi)[None, :, None] * e2
    )
    return dirs.reshape(-1, 3), np.repeat(wu, n_phi) * (2 * np.pi / n_phi)


def test_strong_anisotropy_converges_with_l_max():
    """Fibres at contrast 10⁴: the displacement keeps converging with l_max to the plane-wave
    reference (no SH, a fine product rule about the fibre axis, converged to ~1e-12), ≤ 1e-6 at
    l_max 30. The fixed Lebedev rule stalled at 1.7e-3 for every l_max."""
    material, axis = fibre_composite()
    dirs, weights = axis_product_rule(axis, 1000, 200)
    force = np.array([0.3, -0.5, 1.0])
    m_inv_f = np.linalg.inv(material.acoustic_tensor(dirs)) @ force
    x = sample_offsets(8, seed=21)
    plane = np.sqrt(np.pi) / EPS * np.exp(-(((x @ dirs.T) / EPS) ** 2))  # Φ(x·ξ̂), Gaussian
    reference = (plane * weights) @ m_inv_f / (2 * np.pi) ** 3
    errors = []
    for l_max in (8, 16, 30):
        kernel = GreenKernel(material, l_max=l_max, radial=GaussianRadial(EPS))
        errors.append(rel_err(kernel.displacement(x, np.zeros(3), force), reference))
    assert errors[0] > errors[1] > errors[2] and errors[2] <= 1e-6, errors


def test_material_rule_keeps_lebedev_when_smooth_and_grades_when_peaked():
    from gogreen_core.physics.quadrature import material_rule

    for material in (MATERIALS["cubic"], MATERIALS["isotropic"], MATERIALS["general21"]):
        nodes, weights = material_rule(material, 8)
        assert len(nodes) == 5810  # the paper's Lebedev rule: M⁻¹ smooth enough
    material, axis = fibre_composite(seed=4)
    nodes, weights = material_rule(material, 8)
    np.testing.assert_allclose(np.linalg.norm(nodes, axis=1), 1.0, rtol=1e-14)
    assert abs(weights.sum() - 4 * np.pi) < 1e-12
    # the l = 0 coefficient (mean of M⁻¹) and an l = 2 moment against a fine product rule

    def moments(rule_nodes, rule_weights):
        m_inv = np.linalg.inv(material.acoustic_tensor(rule_nodes))
        xz = rule_nodes[:, 0] * rule_nodes[:, 2]
        return np.einsum("q,qij->ij", rule_weights, m_inv), np.einsum(
            "q,q,qij->ij", rule_weights, xz, m_inv
        )

    fine = moments(*axis_product_rule(axis, 1500, 96))
    for got, want in zip(moments(nodes, weights), fine, strict=True):
        assert rel_err(got, want) < 1e-11


def test_openmp_threads_wait_passively_unless_the_user_chose():
    """Idle OpenMP worker threads sleep instead of spinning on shared cores (see _expansion)."""
    script = "import os, gogreen_core; print(os.environ['OMP_WAIT_POLICY'])"
    for given, expected in ((None, "passive"), ("active", "active")):
        env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
        if given is not None:
            env["OMP_WAIT_POLICY"] = given
        result = subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
        )
        assert result.stdout.split()[-1] == expected


def test_reweighting_a_kernel_needs_no_quadrature_and_is_exact():
    """with_degree_weights gives bit for bit the kernel built with those weights, and its
    output maps act on each degree's displacement (the wrinkle brush's normal projection)."""
    material = Material.orthotropic(
        young=(1.0, 0.6, 12.0), shear=(0.8, 0.9, 0.3), poisson=(0.45, 0.03, 0.03)
    )
    weights = np.array([1.0, 0.5, 2.0, 3.0, 0.1, 7.0, 1.0, 1.0, 4.0])
    built = GreenKernel(material, 8, GaussianRadial(0.3), weights)
    reweighted = GreenKernel(material, 8, GaussianRadial(0.3)).with_degree_weights(weights)
    points = np.random.default_rng(1).normal(size=(64, 3))
    assert np.array_equal(built.green(points), reweighted.green(points))
    assert np.array_equal(built.green_gradient(points), reweighted.green_gradient(points))
    normal = np.array([0.2, 0.3, 0.9]) / np.linalg.norm([0.2, 0.3, 0.9])
    maps = np.array([np.eye(3) if l < 4 else np.outer(normal, normal) for l in range(9)])
    mapped = built.with_degree_weights(weights, maps)
    low = built.with_degree_weights(weights * (np.arange(9) < 4))
    high = built.with_degree_weights(weights * (np.arange(9) >= 4))
    force, load = np.array([0.3, -1.0, 0.5]), np.random.default_rng(3).normal(size=(3, 3))
    expected = low.displacement(points, np.zeros(3), force) + high.displacement(
        points, np.zeros(3), force
    ) @ np.outer(normal, normal)
    assert np.allclose(mapped.displacement(points, np.zeros(3), force), expected, atol=1e-15)
    expected = low.affine_displacement(points, np.zeros(3), load) + high.affine_displacement(
        points, np.zeros(3), load
    ) @ np.outer(normal, normal)
    assert np.allclose(mapped.affine_displacement(points, np.zeros(3), load), expected, atol=1e-15)
    with pytest.raises(ValueError, match="output_maps"):
        built.with_degree_weights(weights, maps[:3])
