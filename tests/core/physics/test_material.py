import numpy as np
import pytest

from gogreen_core import Material
from gogreen_core.physics.material import tensor_to_voigt, voigt_to_tensor
from gogreen_core.sculpt.schema import parse_material


def random_rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def random_spd_voigt(seed: int) -> np.ndarray:
    a = np.random.default_rng(seed).normal(size=(6, 6))
    return a @ a.T + 0.5 * np.eye(6)


def test_isotropic_lame_relations():
    m = Material.isotropic(2.0, 0.25)
    lam, mu = 2.0 * 0.25 / (1.25 * 0.5), 2.0 / 2.5
    assert np.allclose(m.voigt[0, 1], lam) and np.allclose(m.voigt[3, 3], mu)
    assert m == Material.from_lame(lam, mu)


def test_voigt_order_and_tensor_symmetries():
    c6 = random_spd_voigt(0)
    m = Material.from_voigt(c6)
    c = m.tensor
    assert np.allclose(c, c.transpose(1, 0, 2, 3))
    assert np.allclose(c, c.transpose(0, 1, 3, 2))
    assert np.allclose(c, c.transpose(2, 3, 0, 1))
    assert c[1, 2, 0, 1] == c6[3, 5]  # 23 and 12 positions
    assert c[0, 2, 2, 2] == c6[4, 2]
    assert np.array_equal(tensor_to_voigt(voigt_to_tensor(c6)), m.voigt)


def test_orthotropic_compliance_and_directional_young():
    m = Material.orthotropic(young=(1, 2, 3), shear=(0.5, 0.6, 0.7), poisson=(0.2, 0.1, 0.3))
    s = m.compliance
    assert np.allclose(np.diag(s), [1, 1 / 2, 1 / 3, 1 / 0.5, 1 / 0.6, 1 / 0.7])
    assert np.isclose(s[0, 1], -0.2) and np.isclose(s[1, 2], -0.3 / 2)
    assert np.allclose(m.directional_young(np.eye(3)), [1, 2, 3])


def test_transversely_isotropic_is_isotropic_in_plane():
    m = Material.transversely_isotropic(2.0, 5.0, 0.3, 0.2, 0.8)
    rz = np.array([[np.cos(0.7), -np.sin(0.7), 0], [np.sin(0.7), np.cos(0.7), 0], [0, 0, 1]])
    assert np.allclose(m.rotated(rz).voigt, m.voigt)
    assert np.isclose(m.voigt[5, 5], 2.0 / (2 * 1.3))


def test_rotation_composes_and_preserves_isotropy():
    m = Material.from_voigt(random_spd_voigt(1))
    r1, r2 = random_rotation(2), random_rotation(3)
    assert np.allclose(m.rotated(r1).rotated(r2).voigt, m.rotated(r2 @ r1).voigt)
    iso = Material.isotropic(1.0, 0.3)
    assert np.allclose(iso.rotated(r1).voigt, iso.voigt)
    assert np.allclose(m.rotated(r1).rotated(r1.T).voigt, m.voigt)


def test_serialization_round_trip():
    m = Material.from_voigt(random_spd_voigt(4))
    assert parse_material(m.to_dict()) == m  # the schema reads what to_dict writes


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: Material.isotropic(float("nan"), 0.3), "finite"),
        (lambda: Material.isotropic(1.0, float("inf")), "finite"),
        (lambda: Material.isotropic(0.0, 0.3), "> 0"),
        (lambda: Material.isotropic(-1.0, 0.3), "> 0"),
        (lambda: Material.isotropic(1.0, 0.5), "(-1, 1/2)"),
        (lambda: Material.isotropic(1.0, -1.0), "(-1, 1/2)"),
        (lambda: Material.from_lame(1.0, 0.0), "mu must be > 0"),
        (lambda: Material.from_lame(-1.0, 1.0), "bulk modulus"),
        (lambda: Material.from_voigt(np.eye(5)), "6x6"),
        (lambda: Material.from_voigt(np.eye(6) + np.triu(np.ones((6, 6)), 1)), "not symmetric"),
        (lambda: Material.from_voigt(np.diag([1, 1, 1, 1, 1, -1.0])), "not positive definite"),
        (lambda: Material.from_voigt(np.full((6, 6), np.nan)), "finite"),
        (lambda: Material.orthotropic((1, 1, 1), (1, 1, 1), (0.6, 0.6, 0.6)), "1 - nu12*nu21"),
        (
            lambda: Material.orthotropic((1, 4, 1), (1, 1, 1), (0.6, 0.1, 0.1)),
            "|nu12| < sqrt(E1/E2)",
        ),
        (lambda: Material.orthotropic((1, 1, 1), (1, 1, 0), (0.1, 0.1, 0.1)), "G12"),
        (lambda: Material.orthotropic((1, 1), (1, 1, 1), (0.1, 0.1, 0.1)), "shape (3,)"),
        (lambda: Material.transversely_isotropic(1, 1, 1.2, 0.1, 1), "poisson_plane"),
        (lambda: Material.isotropic(1, 0.3).rotated(np.diag([1, 1, -1.0])), "determinant -1"),
        (lambda: Material.isotropic(1, 0.3).rotated(2 * np.eye(3)), "not orthonormal"),
        (lambda: Material.isotropic(1, 0.3).rotated(np.eye(2)), "(3, 3)"),
        (lambda: Material.isotropic(1, 0.3).rotated(np.full((3, 3), np.nan)), "finite"),
    ],
)
def test_bad_input_raises_value_error_naming_the_condition(build, message):
    with pytest.raises(ValueError, match=None) as info:
        build()
    assert message in str(info.value)
