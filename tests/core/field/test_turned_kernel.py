"""A kernel turned with its material (Wigner-D rotation of P_lm) equals one built by quadrature
on the turned material, and G'(x) = F G(Fᵀx) Fᵀ."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.physics.material import Material
from gogreen_core.physics.sph import real_sph_harm
from gogreen_core.physics.sph_rotation import real_wigner_d


def _laminate() -> Material:
    return Material.orthotropic((1.0, 1.0, 30.0), (0.5, 0.5, 0.4), (0.3, 0.1, 0.1)).rotated(
        Rotation.from_euler("xyz", (0.3, 0.7, -0.2)).as_matrix()
    )


@pytest.mark.parametrize("reflect", [False, True])
def test_wigner_d_turns_the_harmonics(reflect: bool) -> None:
    q = Rotation.random(random_state=5).as_matrix()
    if reflect:
        q = q @ np.diag([1.0, -1.0, 1.0])  # a reflection: the matrices take it as it is
    blocks = real_wigner_d(q, 13)
    eta = np.random.default_rng(1).normal(size=(40, 3))
    eta /= np.linalg.norm(eta, axis=1)[:, None]
    y, y_turned = real_sph_harm(eta, 13), real_sph_harm(eta @ q.T, 13)
    for l, block in enumerate(blocks):
        cols = slice(l * l, (l + 1) ** 2)
        assert np.abs(y_turned[:, cols] - y[:, cols] @ block.T).max() < 1e-12
        assert np.abs(block @ block.T - np.eye(2 * l + 1)).max() < 1e-12


def test_wigner_d_refuses_a_matrix_that_is_not_orthogonal() -> None:
    with pytest.raises(ValueError, match="orthogonal"):
        real_wigner_d(np.diag([1.0, 2.0, 1.0]), 4)


@pytest.mark.parametrize("l_max", [8, 12])
def test_turned_kernel_is_the_kernel_of_the_turned_material(l_max: int) -> None:
    material = _laminate()
    f = Rotation.random(random_state=7).as_matrix()
    kernel = GreenKernel(material, l_max)
    turned = kernel.turned(f)
    built = GreenKernel(material.rotated(f), l_max)
    x = np.random.default_rng(2).normal(size=(100, 3))
    g, g_built = turned.green(x), built.green(x)
    assert np.abs(g - g_built).max() < 1e-9 * np.abs(g_built).max()
    d, d_built = turned.green_gradient(x), built.green_gradient(x)
    assert np.abs(d - d_built).max() < 1e-9 * np.abs(d_built).max()
    # G'(x) = F G(Fᵀ x) Fᵀ, with the kernel's own truncation
    expected = np.einsum("ia,nab,jb->nij", f, kernel.green(x @ f), f)
    assert np.abs(g - expected).max() < 1e-12 * np.abs(expected).max()
    assert turned.material == built.material or np.allclose(
        turned.material.voigt, built.material.voigt
    )


def test_turned_kernel_refuses_a_reflection() -> None:
    with pytest.raises(ValueError, match="reflection"):
        GreenKernel(_laminate(), 4).turned(np.diag([1.0, 1.0, -1.0]))
