"""Honest units (issue 15 item 5): an affine brush's `amount` is the strain (scale, pinch) or the
angle in radians (twist) at the brush centre, measured here by finite differences of the actual
displacement of points around the centre, for isotropic and anisotropic materials."""

import numpy as np
import pytest
from scipy.linalg import logm

from gogreen_core import Material
from gogreen_core.physics.radial import KelvinletRadial
from gogreen_core.sculpt.brushes import Brush, BrushEvent, affine_load_shape
from gogreen_core.sculpt.sculptor import Sculptor

ROTATION = np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
MATERIALS = {
    "isotropic": Material.isotropic(1.0, 0.3),
    "nearly incompressible": Material.isotropic(1.0, 0.45),
    "cubic, rotated": Material.cubic(3.0, 1.5, 0.4).rotated(ROTATION),
    "fibres": Material.transversely_isotropic(
        young_plane=1.0, young_axial=20.0, poisson_plane=0.35, poisson_axial=0.05, shear_axial=0.5
    ).rotated(ROTATION),
}
CENTER = np.array([0.1, -0.2, 0.3])
STEP = 1e-5  # of the finite differences, model units (ε = 0.2 · model size ≈ 0.35)


def deformation_gradient(kind, material, amount, axis, direction, substeps=8):
    """F = ∂x'/∂x at the brush centre after one event, by central differences of the actual
    displacement of six probe vertices around it."""
    probes = CENTER + STEP * np.vstack([np.eye(3), -np.eye(3)])
    corners = np.array([[-1.0, -1, -1], [1, 1, 1], [1, -1, 0]])  # the model: a unit-ish box
    vertices = np.vstack([probes, corners])
    sculptor = Sculptor(vertices, [[6, 7, 8]], material=material)
    brush = Brush(kind, radius=0.2, influence=np.inf, substeps=substeps)
    event = BrushEvent(CENTER, amount=amount, axis=axis, direction=direction)
    sculptor.apply_brush(brush, [event])
    moved = sculptor.vertices[:6]
    return ((moved[:3] - moved[3:]) / (2 * STEP)).T  # [i, p] = ∂x'_i/∂x_p


def along(matrix, shape):
    """Component of ``matrix`` along the load shape: (M : B) / (B : B)."""
    return float(np.sum(matrix * shape) / np.sum(shape * shape))


AXIS = np.array([0.2, -0.4, 1.0])
DIRECTION = np.array([1.0, 0.5, 0.0])


@pytest.mark.parametrize("material", MATERIALS.values(), ids=MATERIALS.keys())
@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_a_small_amount_is_the_displacement_gradient_at_the_centre(kind, material):
    amount = 1e-4
    shape = affine_load_shape(kind, AXIS, DIRECTION)
    gradient = deformation_gradient(kind, material, amount, AXIS, DIRECTION) - np.eye(3)
    # the displacement gradient's component along the brush's pattern is `amount`
    assert along(gradient, shape) == pytest.approx(amount, rel=1e-3)
    if material is MATERIALS["isotropic"]:  # and, by symmetry, it is the whole gradient
        assert np.abs(gradient - amount * shape).max() < 1e-3 * amount


@pytest.mark.parametrize("material", MATERIALS.values(), ids=MATERIALS.keys())
@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_a_large_amount_is_the_logarithmic_strain_or_the_angle(kind, material):
    amount = 0.4
    shape = affine_load_shape(kind, AXIS, DIRECTION)
    f = deformation_gradient(kind, material, amount, AXIS, DIRECTION)
    # an event is a flow over pseudo-time [0, 1] with a fixed centre: F = exp(amount · B) along
    # the pattern, so the log strain (scale, pinch) or the angle (twist) is `amount`
    assert along(np.real(logm(f)), shape) == pytest.approx(amount, rel=1e-5)


def test_twist_turns_an_isotropic_centre_by_amount_radians():
    angle = 0.7
    f = deformation_gradient("twist", MATERIALS["isotropic"], angle, AXIS, None)
    assert np.abs(f.T @ f - np.eye(3)).max() < 1e-5  # a rotation
    assert np.arccos((np.trace(f) - 1) / 2) == pytest.approx(angle, rel=1e-5)
    assert f @ AXIS == pytest.approx(AXIS, abs=1e-5)  # about the axis


def test_scale_stretches_an_isotropic_centre_by_exp_amount():
    f = deformation_gradient("scale", MATERIALS["isotropic"], 0.3, None, None)
    assert np.abs(f - np.exp(0.3) * np.eye(3)).max() < 1e-5


def test_strength_multiplies_the_amount_and_the_falloff_does_not_change_it():
    shape = affine_load_shape("pinch", AXIS, DIRECTION)
    probes = CENTER + STEP * np.vstack([np.eye(3), -np.eye(3)])
    vertices = np.vstack([probes, [[-1.0, -1, -1], [1, 1, 1], [1, -1, 0]]])
    sculptor = Sculptor(vertices, [[6, 7, 8]], falloff=KelvinletRadial(1.0))
    event = BrushEvent(CENTER, amount=1e-4, axis=AXIS, direction=DIRECTION)
    sculptor.apply_brush(Brush("pinch", radius=0.05, strength=3.0, influence=np.inf), [event])
    moved = sculptor.vertices[:6]
    gradient = ((moved[:3] - moved[3:]) / (2 * STEP)).T - np.eye(3)
    assert along(gradient, shape) == pytest.approx(3e-4, rel=1e-3)
