"""Safe falloffs (issue 13, item 4): no falloff an artist can draw makes one brush event move a
vertex more than a small multiple of the cursor motion, flip a face or write NaN; ordinary
falloffs keep f = G(0)⁻¹ Δ exactly."""

import numpy as np
import pytest

from gogreen_core import Material
from gogreen_core.files.presets import builtin_presets
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, SplineRadial
from gogreen_core.sculpt.brushes import (
    Brush,
    BrushEvent,
    affine_load_shape,
    mirror_signs,
)
from gogreen_core.sculpt.brushes.affine import centre_jacobian
from gogreen_core.sculpt.falloff_safety import MAX_GRAB_RATIO
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.validation import ParameterError


# The brush physics moved from Sculptor's private methods to the brush table (its rows' load,
# limits and field bound, given the engine's stroke context).
def _context(sculptor):
    return sculptor._strokes.context(sculptor._kernels)


def _load(sculptor, brush, kernel, event):
    return brush.type.load(_context(sculptor), brush, kernel, event)


def _affine_limits(sculptor, brush, shape):
    return brush.type.limits(_context(sculptor), brush, shape)


def _field_bound(sculptor, brush, kernel):
    return brush.type.field_bound(_context(sculptor), brush, kernel)


L_MAX = 8
#: Brush radius relative to the model size (2 for the unit sphere): ε = 0.3.
RADIUS = 0.15
MATERIALS = {
    "isotropic": Material.isotropic(1.0, 0.3),
    "cubic": Material.cubic(3.0, 1.5, 0.4).rotated(
        np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
    ),
    # a laminate-like material: 100 times stiffer in the plane than across it
    "strongly anisotropic": Material.transversely_isotropic(100.0, 1.0, 0.3, 0.02, 0.5),
}


def _spline(l_max: int = L_MAX) -> SplineRadial:
    return SplineRadial.from_profile(GaussianRadial(1.0), l_max)


def _edited(edit) -> SplineRadial:
    """The Gaussian falloff as splines, with its R₀ control values edited by ``edit``."""
    falloff = _spline()
    rho, value = falloff.curve("R", 0)
    return falloff.with_curves({("R", 0): (rho, edit(rho, value.copy()))})


def _dip(rho, value):
    value[:3] *= [0.08, 0.3, 0.8]  # the measured case: 13× the cursor motion before
    return value


def _zero_at_centre(rho, value):
    value[0] = 0.0  # the measured case: 10¹⁶× the cursor motion, 6,893 flipped faces
    return value


def _negative_near_centre(rho, value):
    value[:2] = [-0.5 * value[0], -0.1 * value[1]]
    return value


def _wiggles(rho, value):
    return value * (1 + 0.8 * np.sin(7 * rho))


def _random_wiggles(seed):
    def edit(rho, value):
        rng = np.random.default_rng(seed)
        return value * (1 + rng.uniform(-1.0, 1.0, len(rho)))

    return edit


CURVES = {
    "dip near 0": _dip,
    "zero at 0": _zero_at_centre,
    "negative near 0": _negative_near_centre,
    "wiggles": _wiggles,
    **{f"random wiggles {seed}": _random_wiggles(seed) for seed in range(3)},
}
#: Cursor motions in units of ε: tiny up to half the brush radius.
EVENT_SIZES = (1e-4, 0.05, 0.5)


@pytest.fixture(scope="module")
def sphere():
    return icosphere(3)


def _face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


def _assert_safe_events(sculptor, kind, radius, centres):
    """Single ``kind`` events of every size in :data:`EVENT_SIZES` (units of ε) at each of
    ``centres`` (vertex indices), each undone: finite, no vertex moved more than 3× the cursor
    motion, no face turned over."""
    vertices, faces = sculptor.vertices.copy(), sculptor.faces
    eps = radius * sculptor.model_size
    normals = _face_normals(vertices, faces)
    direction = np.array([0.6, -0.3, 0.74])
    direction /= np.linalg.norm(direction)
    for index in centres:
        for size in EVENT_SIZES:
            delta = size * eps * direction
            sculptor.apply_brush(Brush(kind, radius=radius), [BrushEvent(vertices[index], delta)])
            moved = sculptor.vertices.copy()
            sculptor.undo()
            label = f"{kind}, cursor motion {size} ε at vertex {index}"
            assert np.all(np.isfinite(moved)), label
            motion = np.linalg.norm(moved - vertices, axis=1).max()
            assert motion <= 3 * size * eps, f"{label}: moved {motion / (size * eps):.3g}×"
            turned = np.einsum("ij,ij->i", normals, _face_normals(moved, faces)) <= 0
            assert not turned.any(), f"{label}: {turned.sum()} faces flipped"


@pytest.mark.parametrize("material", list(MATERIALS))
@pytest.mark.parametrize("curve", list(CURVES))
def test_edited_falloffs_never_wreck_the_mesh(sphere, curve, material):
    vertices, faces = sphere
    sculptor = Sculptor(
        vertices, faces, material=MATERIALS[material], l_max=L_MAX, falloff=_edited(CURVES[curve])
    )
    for kind in ("grab", "grab_biscale"):
        _assert_safe_events(sculptor, kind, RADIUS, [7])


@pytest.mark.parametrize("curve", ["dip near 0", "zero at 0", "wiggles", None])
@pytest.mark.parametrize("material", ["wrinkle preset", "1000:1 transversely isotropic"])
def test_the_wrinkle_brush_with_its_default_weights_never_wrecks_the_mesh(sphere, curve, material):
    vertices, faces = sphere
    materials = {
        "wrinkle preset": next(p for p in builtin_presets() if p.brush.kind == "wrinkle").material,
        "1000:1 transversely isotropic": Material.transversely_isotropic(
            1000.0, 1.0, 0.3, 0.02, 0.5
        ),
    }
    sculptor = Sculptor(
        vertices,
        faces,
        material=materials[material],
        falloff=GaussianRadial(1.0) if curve is None else _edited(CURVES[curve]),
    )
    _assert_safe_events(sculptor, "wrinkle", RADIUS, [7, 40])


@pytest.mark.parametrize(
    "falloff",
    [GaussianRadial(1.0), KelvinletRadial(1.0), SplineRadial.from_profile(KelvinletRadial(1.0), 8)],
    ids=["gaussian", "kelvinlet", "spline"],
)
@pytest.mark.parametrize("kind", ["grab", "grab_biscale", "grab_triscale", "wrinkle"])
def test_ordinary_falloffs_keep_the_exact_centre_normalization(sphere, falloff, kind):
    """f = G(0)⁻¹ Δ bit for bit: the grabbed point follows the cursor exactly."""
    vertices, faces = sphere
    for preset in [None, *builtin_presets()]:
        material = MATERIALS["cubic"] if preset is None else preset.material
        sculptor = Sculptor(vertices, faces, material=material, l_max=L_MAX, falloff=falloff)
        brush = Brush(kind, radius=RADIUS)
        event = BrushEvent(vertices[3], 0.5 * RADIUS * sculptor.model_size * np.array([1, 2, -1]))
        full = sculptor.kernel(Brush("grab", radius=RADIUS))
        force = np.linalg.solve(
            full.with_radial(sculptor.kernel(brush).radial).green(np.zeros((1, 3)))[0], event.delta
        )
        load, _ = _load(sculptor, brush, sculptor.kernel(brush), event)
        assert np.array_equal(load, force), (kind, preset and preset.name)


@pytest.mark.parametrize("falloff", [GaussianRadial(1.0), KelvinletRadial(1.0)], ids=["g", "k"])
@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_ordinary_affine_loads_keep_the_exact_centre_normalization(sphere, falloff, kind):
    vertices, faces = sphere
    rng = np.random.default_rng(5)
    materials = [*MATERIALS.values(), *(preset.material for preset in builtin_presets())]
    for material in materials:
        sculptor = Sculptor(vertices, faces, material=material, falloff=falloff)
        brush = Brush(kind, radius=RADIUS)
        kernel = sculptor.kernel(brush)
        for _ in range(3):
            axis, direction = rng.normal(size=(2, 3))
            event = BrushEvent(vertices[9], amount=0.3, axis=axis, direction=direction)
            shape = affine_load_shape(kind, event.axis, event.direction)
            jacobian = centre_jacobian(kernel, event.center, shape)
            response = float(np.sum(jacobian * shape) / np.sum(shape * shape))
            load, _ = _load(sculptor, brush, kernel, event)
            assert np.array_equal(load, shape * (0.3 / response)), material


def test_ordinary_grab_moves_the_picked_vertex_exactly(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, material=MATERIALS["strongly anisotropic"])
    delta = 0.5 * RADIUS * sculptor.model_size * np.array([0.3, 0.5, 0.81])
    sculptor.apply_brush(Brush("grab", radius=RADIUS), [BrushEvent(vertices[11], delta)])
    assert np.abs(sculptor.vertices[11] - vertices[11] - delta).max() < 1e-12


def _flat_centre_gradient(rho, value):
    value[:6] = 0.0  # ℛ₁ = 0 for ρ ≤ 1.25: the velocity gradient at the centre vanishes
    return value


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
@pytest.mark.parametrize("material", list(MATERIALS))
def test_affine_brushes_with_a_vanishing_centre_response_stay_bounded(sphere, kind, material):
    vertices, faces = sphere
    falloff = _spline()
    rho, value = falloff.curve("dR", 1)
    falloff = falloff.with_curves({("dR", 1): (rho, _flat_centre_gradient(rho, value))})
    sculptor = Sculptor(vertices, faces, material=MATERIALS[material], falloff=falloff)
    gaussian = Sculptor(vertices, faces, material=MATERIALS[material])
    eps = RADIUS * sculptor.model_size
    brush = Brush(kind, radius=RADIUS)
    normals = _face_normals(vertices, faces)
    for amount in (1e-3, 0.05, 0.2):
        event = BrushEvent(vertices[5], amount=amount, axis=vertices[5], direction=[1, 2, 0])
        sculptor.apply_brush(brush, [event])
        moved = sculptor.vertices.copy()
        sculptor.undo()
        gaussian.apply_brush(brush, [event])
        reference = np.linalg.norm(gaussian.vertices - vertices, axis=1).max()
        gaussian.undo()
        assert np.all(np.isfinite(moved))
        motion = np.linalg.norm(moved - vertices, axis=1).max()
        # the centre normalization moved them 12-17 amount·ε, the Gaussian ~0.25 amount·ε
        assert (
            motion
            <= 1.01
            * _affine_limits(sculptor, brush, affine_load_shape(kind, event.axis, event.direction))[
                0
            ]
            * amount
            * eps
        )
        assert motion <= 3 * reference, f"amount {amount}: {motion / reference:.3g}× the Gaussian"
        turned = np.einsum("ij,ij->i", normals, _face_normals(moved, faces)) <= 0
        assert not turned.any(), f"amount {amount}: {turned.sum()} faces flipped"


def test_a_falloff_that_is_zero_everywhere_is_refused(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces)
    falloff = _spline(4)
    for kind, l in falloff.curve_keys():
        rho, value = falloff.curve(kind, l)
        falloff = falloff.with_curves({(kind, l): (rho, 0 * value)})
    with pytest.raises(ParameterError, match="zero everywhere") as info:
        sculptor.change_settings(falloff=falloff, l_max=4)
    assert info.value.parameter == "falloff"
    assert sculptor.settings.falloff.kind_name == "gaussian"  # nothing changed


def test_a_grab_whose_field_is_zero_is_refused_and_moves_nothing(sphere):
    vertices, faces = sphere
    falloff = _spline(4)
    for l in (0, 2, 4):  # G vanishes; ∇G (affine brushes) does not
        rho, value = falloff.curve("R", l)
        falloff = falloff.with_curves({("R", l): (rho, 0 * value)})
    sculptor = Sculptor(vertices, faces, l_max=4, falloff=falloff)
    event = BrushEvent(vertices[0], np.array([0.01, 0.0, 0.0]))
    with pytest.raises(ParameterError, match="zero everywhere") as info:
        sculptor.apply_brush(Brush("grab", radius=RADIUS), [event])
    assert info.value.parameter.endswith("falloff")
    assert np.array_equal(sculptor.vertices, vertices)


def test_the_bound_is_cached_per_kernel_not_per_event(sphere):
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, falloff=_edited(_dip))
    brush = Brush("grab", radius=RADIUS)
    event = BrushEvent(vertices[0], np.array([0.01, 0.0, 0.0]))
    sculptor.apply_brush(brush, [event, event])
    first = _field_bound(sculptor, brush, sculptor.kernel(brush))
    # another radius: the same samples (they are taken at ε = 1)
    other = Brush("grab", radius=2 * RADIUS)
    assert _field_bound(sculptor, other, sculptor.kernel(other)) is first
    sculptor.change_settings(falloff=_edited(_wiggles))
    assert _field_bound(sculptor, brush, sculptor.kernel(brush)) is not first


def test_mirrored_brushes_stay_bounded(sphere):
    """Each mirror image of the load is bounded; images overlapping add up at most 2^k."""
    vertices, faces = sphere
    sculptor = Sculptor(vertices, faces, falloff=_edited(_zero_at_centre))
    eps = RADIUS * sculptor.model_size
    delta = 0.5 * eps * np.array([1.0, 0.0, 0.0])
    brush = Brush("grab", radius=RADIUS, symmetry="x")
    sculptor.apply_brush(brush, [BrushEvent(vertices[2], delta)])
    motion = np.linalg.norm(sculptor.vertices - vertices, axis=1).max()
    images = len(mirror_signs("x"))
    assert motion <= images * MAX_GRAB_RATIO * np.linalg.norm(delta) * 1.01
