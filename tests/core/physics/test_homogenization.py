import numpy as np
import pytest

from gogreen_core.physics.homogenization import (
    bimaterial,
    check_phases,
    homogenize,
    homogenize_detailed,
    reuss_bound,
    voigt_bound,
)
from gogreen_core.physics.material import Material
from gogreen_core.physics.patterns import checkerboard, layered, random_pattern, spheres
from gogreen_core.physics.symmetry import describe_symmetry

# Proper rotations taking axis z to the named axis (used to rotate the z-normal Backus tensor).
_Z_TO = {
    "z": np.eye(3),
    "x": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),
    "y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]),
}


def backus_z(fraction_b: float, mat_a: Material, mat_b: Material) -> np.ndarray:
    """Exact laminate tensor (normal z) of ../shared/MATH.md for isotropic layers."""
    lam = np.array([mat_a.voigt[0, 1], mat_b.voigt[0, 1]])
    mu = np.array([mat_a.voigt[3, 3], mat_b.voigt[3, 3]])
    w = np.array([1.0 - fraction_b, fraction_b])

    def avg(v: np.ndarray) -> float:
        return float(w @ v)

    c33 = 1.0 / avg(1.0 / (lam + 2 * mu))
    c13 = avg(lam / (lam + 2 * mu)) * c33
    c11 = avg(4 * mu * (lam + mu) / (lam + 2 * mu)) + avg(lam / (lam + 2 * mu)) ** 2 * c33
    c = np.zeros((6, 6))
    c[0, 0] = c[1, 1] = c11
    c[2, 2] = c33
    c[0, 2] = c[2, 0] = c[1, 2] = c[2, 1] = c13
    c[0, 1] = c[1, 0] = c11 - 2 * avg(mu)
    c[3, 3] = c[4, 4] = 1.0 / avg(1.0 / mu)
    c[5, 5] = avg(mu)
    return c


def rel_err(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


# -- exact cases ------------------------------------------------------------------------------
@pytest.mark.parametrize("which", [0, 1])
def test_homogeneous_grid_returns_the_phase(which):
    mats = bimaterial(2.0, 0.25, contrast=50.0)
    ph = np.full((8, 8, 8), which, dtype=np.int8)
    assert homogenize(ph, mats) == mats[which]


def test_nearly_equal_phases_give_their_average_through_the_solver():
    a = Material.isotropic(1.0, 0.3)
    b = Material.isotropic(1.0 + 1e-9, 0.3)
    ph = random_pattern(8, 0.4, seed=3)
    res = homogenize_detailed(ph, (a, b))
    assert res.iterations >= 1
    assert rel_err(res.material.voigt, a.voigt) < 1e-8


@pytest.mark.parametrize("normal", ["x", "y", "z"])
@pytest.mark.parametrize(
    ("n", "fraction", "periods", "contrast", "nu_b"),
    [(8, 0.5, 1, 10.0, 0.3), (12, 1 / 3, 2, 1e4, 0.1), (9, 2 / 9, 1, 100.0, 0.45)],
)
def test_laminate_matches_backus(normal, n, fraction, periods, contrast, nu_b):
    mats = (Material.isotropic(1.0, 0.3), Material.isotropic(contrast, nu_b))
    ph = layered(n, normal=normal, fraction=fraction, periods=periods)
    exact = Material(backus_z(ph.mean(), *mats)).rotated(_Z_TO[normal])
    got = homogenize(ph, mats)
    assert rel_err(got.voigt, exact.voigt) < 1e-6
    # and it is transversely isotropic about the normal
    sym = describe_symmetry(got)
    assert (sym.symmetry_class, sym.axis) == ("transversely isotropic", normal)


def test_laminate_on_smallest_grid():
    mats = (Material.isotropic(1.0, 0.2), Material.isotropic(300.0, 0.4))
    ph = np.zeros((2, 2, 2), dtype=np.int8)
    ph[:, :, 1] = 1
    assert rel_err(homogenize(ph, mats).voigt, backus_z(0.5, *mats)) < 1e-9


# -- symmetry, bounds, rotation ---------------------------------------------------------------
@pytest.mark.parametrize("contrast", [10.0, 1e4])
def test_checkerboard_is_cubic(contrast):
    mats = bimaterial(1.0, 0.3, contrast)
    c = homogenize(checkerboard(8), mats).voigt
    scale = np.abs(c).max()
    d = np.diag(c)
    assert np.ptp(d[:3]) < 1e-8 * scale and np.ptp(d[3:]) < 1e-8 * scale
    assert np.ptp([c[0, 1], c[0, 2], c[1, 2]]) < 1e-8 * scale
    assert np.abs(c[:3, 3:]).max() < 1e-8 * scale
    # genuinely cubic, not isotropic: Zener ratio 2 C44 / (C11 - C12) away from 1
    assert abs(2 * d[3] / (d[0] - c[0, 1]) - 1.0) > 0.05
    sym = describe_symmetry(c)
    assert sym.symmetry_class == "cubic"
    assert sym.group_count == 3
    expected = np.full((6, 6), -1)
    expected[:3, :3] = 1
    expected[[0, 1, 2], [0, 1, 2]] = 0
    expected[[3, 4, 5], [3, 4, 5]] = 2
    assert np.array_equal(sym.groups, expected)


def loewner_min(a: np.ndarray) -> float:
    return float(np.linalg.eigvalsh(0.5 * (a + a.T))[0])


@pytest.mark.parametrize(
    ("seed", "fraction", "contrast"), [(0, 0.5, 10.0), (1, 0.3, 100.0), (2, 0.7, 1e4)]
)
def test_random_pattern_between_reuss_and_voigt(seed, fraction, contrast):
    mats = (Material.isotropic(1.0, 0.3), Material.isotropic(contrast, 0.2))
    ph = random_pattern(10, fraction, seed=seed)
    f = ph.mean()
    c = homogenize(ph, mats).voigt
    cv, cr = voigt_bound(f, mats).voigt, reuss_bound(f, mats).voigt
    scale = np.abs(cv).max()
    assert np.array_equal(c, c.T)
    assert loewner_min(c) > 0
    assert loewner_min(cv - c) > -1e-9 * scale
    assert loewner_min(c - cr) > -1e-9 * scale
    # strictly inside: a random two-phase mix is neither uniform strain nor uniform stress
    assert np.trace(cv - c) > 1e-3 * np.trace(cv)
    assert np.trace(c - cr) > 1e-3 * np.trace(cr)


def test_rotated_pattern_gives_rotated_tensor():
    mats = bimaterial(1.0, 0.3, 200.0)
    ph = random_pattern(8, 0.4, seed=7, correlation=0.1)
    base = homogenize(ph, mats)
    # np.rot90 in the (x, y) plane: voxel x' = R x with R the +90 degree rotation about z.
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    got = homogenize(np.rot90(ph, 1, axes=(0, 1)), mats)
    assert rel_err(got.voigt, base.rotated(rz).voigt) < 1e-8
    assert rel_err(got.voigt, base.voigt) > 1e-3  # the pattern is not symmetric: test bites
    # np.transpose(ph, (1, 2, 0)) gives new[i, j, k] = old[k, i, j]: x' = y, y' = z, z' = x.
    cyc = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    got = homogenize(np.transpose(ph, (1, 2, 0)), mats)
    assert rel_err(got.voigt, base.rotated(cyc).voigt) < 1e-8


def test_spheres_converge_under_refinement_and_stay_cubic():
    mats = bimaterial(1.0, 0.3, 1e4)
    coarse = homogenize(spheres(8, 0.2), mats).voigt
    fine = homogenize(spheres(16, 0.2), mats).voigt
    assert describe_symmetry(fine, 1e-6).symmetry_class == "cubic"
    assert rel_err(fine, coarse) < 0.1  # same microstructure, finer voxels


def test_anisotropic_phases_are_accepted():
    soft = Material.cubic(3.0, 1.0, 0.5)
    stiff = Material.isotropic(20.0, 0.25)
    c = homogenize(checkerboard(6), (soft, stiff))
    assert describe_symmetry(c).symmetry_class == "cubic"
    f = 0.5
    cv, cr = voigt_bound(f, (soft, stiff)).voigt, reuss_bound(f, (soft, stiff)).voigt
    assert loewner_min(cv - c.voigt) > -1e-9 and loewner_min(c.voigt - cr) > -1e-9


# -- symmetry description --------------------------------------------------------------------
def test_symmetry_classes_of_known_materials():
    iso = describe_symmetry(Material.isotropic(3.0, 0.3))
    assert iso.symmetry_class == "isotropic" and iso.group_count == 3
    assert iso.groups[0, 0] == iso.groups[2, 2] != iso.groups[0, 1] == iso.groups[1, 2]
    assert iso.groups[3, 3] == iso.groups[5, 5] and iso.groups[0, 3] == -1
    assert np.allclose(iso.values, Material.isotropic(3.0, 0.3).voigt)
    ti = Material.transversely_isotropic(10.0, 3.0, 0.3, 0.2, 1.5)
    assert (describe_symmetry(ti).symmetry_class, describe_symmetry(ti).axis) == (
        "transversely isotropic",
        "z",
    )
    ortho = Material.orthotropic((1.0, 2.0, 3.0), (0.4, 0.5, 0.6), (0.2, 0.25, 0.3))
    assert describe_symmetry(ortho).symmetry_class == "orthotropic"
    cubic = Material.cubic(3.0, 1.0, 0.4)
    assert describe_symmetry(cubic).symmetry_class == "cubic"
    c, s = np.cos(0.3), np.sin(0.3)
    turned = cubic.rotated(np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]))
    assert describe_symmetry(turned).symmetry_class == "other"
    assert describe_symmetry(Material.from_voigt(np.eye(6) + 0.1)).symmetry_class == "other"


def test_fibers_are_tetragonal_about_their_axis():
    from gogreen_core.physics.patterns import fibers

    c = homogenize(fibers(8, axis="y", fraction=0.3), bimaterial(contrast=50.0))
    sym = describe_symmetry(c)
    assert (sym.symmetry_class, sym.axis) == ("tetragonal", "y")


def test_describe_symmetry_rejects_bad_input():
    with pytest.raises(ValueError, match=r"voigt must have shape \(6, 6\)"):
        describe_symmetry(np.eye(5))
    with pytest.raises(ValueError, match="rtol"):
        describe_symmetry(np.eye(6), rtol=-1.0)


# -- solver details ---------------------------------------------------------------------------
def test_progress_is_monotone_and_ends_at_one():
    values = []
    res = homogenize_detailed(random_pattern(8, 0.5, 1), bimaterial(contrast=100.0), values.append)
    assert values[0] == 0.0 and values[-1] == 1.0
    assert np.all(np.diff(values) >= 0)
    assert len(values) >= res.iterations
    assert res.residual <= 1e-5


def test_tolerance_controls_accuracy():
    mats = bimaterial(1.0, 0.3, 1e3)
    ph = random_pattern(8, 0.5, seed=4)
    ref = homogenize(ph, mats, rtol=1e-10).voigt
    loose = homogenize(ph, mats, rtol=1e-3).voigt
    default = homogenize(ph, mats).voigt
    assert rel_err(default, ref) < 1e-8
    assert rel_err(default, ref) < rel_err(loose, ref)


def test_max_iter_reached_raises():
    with pytest.raises(RuntimeError, match="did not converge"):
        homogenize(random_pattern(8, 0.5, 0), bimaterial(contrast=1e4), rtol=1e-12, max_iter=2)


# -- bounds and helpers -----------------------------------------------------------------------
def test_bounds_of_isotropic_phases():
    mats = bimaterial(1.0, 0.3, 10.0)
    assert voigt_bound(0.0, mats) == mats[0]
    assert rel_err(reuss_bound(1.0, mats).voigt, mats[1].voigt) < 1e-12
    f = 0.3
    assert np.allclose(voigt_bound(f, mats).voigt, 0.7 * mats[0].voigt + 0.3 * mats[1].voigt)
    # Reuss shear = harmonic mean
    mu = 1 / (0.7 / mats[0].voigt[3, 3] + 0.3 / mats[1].voigt[3, 3])
    assert np.isclose(reuss_bound(f, mats).voigt[3, 3], mu)
    with pytest.raises(ValueError, match="fraction_b"):
        voigt_bound(1.5, mats)


def test_bimaterial():
    a, b = bimaterial(2.0, 0.25, 100.0)
    assert a == Material.isotropic(2.0, 0.25)
    assert b == Material.isotropic(200.0, 0.25)
    assert bimaterial(contrast=1.0)[0] == bimaterial(contrast=1.0)[1]
    for bad in (0.5, 2e4, float("nan")):
        with pytest.raises(ValueError, match="contrast"):
            bimaterial(contrast=bad)


# -- input validation -------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("phases", "message"),
    [
        (np.zeros((4, 4)), "3D"),
        (np.zeros((4, 4, 4, 1)), "3D"),
        (np.zeros((4, 4, 5)), "cubic"),
        (np.zeros((1, 1, 1)), "n >= 2"),
        (np.full((3, 3, 3), 2), "only 0 and 1"),
        (np.full((3, 3, 3), 0.5), "only 0 and 1"),
        (np.where(np.eye(3)[None] > 0, np.nan, 0.0) * np.ones((3, 1, 1)), "NaN"),
        (np.full((3, 3, 3), np.inf), "infinite"),
        (np.array([["a"]]), "numeric"),
    ],
)
def test_invalid_phases_raise(phases, message):
    with pytest.raises(ValueError, match=message):
        homogenize(phases, bimaterial())


def test_accepted_phase_types():
    ph = checkerboard(4)
    for arr in (ph.astype(bool), ph.astype(float), ph.astype(np.int64), ph.tolist()):
        out = check_phases(arr)
        assert out.dtype == np.int8 and np.array_equal(out, ph)


def test_invalid_materials_raise():
    ph = checkerboard(4)
    with pytest.raises(ValueError, match="pair"):
        homogenize(ph, (Material.isotropic(1, 0.3),))
    with pytest.raises(TypeError, match="Material"):
        homogenize(ph, (Material.isotropic(1, 0.3), np.eye(6)))
