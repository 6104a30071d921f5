"""The legacy wrinkle brush (issue 13, item 6; ``wrinkle_legacy`` since session version 3, what
older sessions call ``wrinkle``): with its default weights and the "Layered sheet wrinkles"
material it ripples the surface, where grab does not; it stays as safe as grab; old sessions
(weights recorded as null) replay as before. The folding wrinkle brush that replaced it:
tests/test_wrinkle_folds.py."""

import json
from dataclasses import replace

import numpy as np
import pytest

from gogreen_core import Sculptor, bimaterial, builtin_presets, homogenize, make_pattern
from gogreen_core.brushes import (
    WRINKLE_LEVEL,
    WRINKLE_RING,
    WRINKLE_TOP_DEGREE,
    Brush,
    BrushEvent,
    default_wrinkle_weights,
    legacy_wrinkle_weights,
)
from gogreen_core.radial import GaussianRadial
from gogreen_core.schema import MAX_DEGREE_WEIGHT
from gogreen_core.settings import Settings
from gogreen_core.shapes import default_model, icosphere

#: The app's camera looks at the model from this side (app/viewport.py HOME_VIEW_DIRECTION).
HOME_VIEW = np.array([0.55, 0.4, 1.0]) / np.linalg.norm([0.55, 0.4, 1.0])


def _wrinkle_preset():
    return next(p for p in builtin_presets() if p.brush.kind == "wrinkle")


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    normals = np.zeros_like(vertices)
    face_normals = np.cross(
        vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]]
    )
    for k in range(3):
        np.add.at(normals, faces[:, k], face_normals)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def _stroke(sculptor: Sculptor, kind: str, radius: float, index: int, direction) -> np.ndarray:
    """Displacement (N, 3) of a 10-event stroke of 0.1 ε per event from vertex ``index``,
    along ``direction`` projected on the surface; undone afterwards."""
    rest = sculptor.vertices.copy()
    normal = _vertex_normals(rest, sculptor.faces)[index]
    along = direction - (direction @ normal) * normal
    delta = 0.1 * radius * sculptor.model_size * along / np.linalg.norm(along)
    events = [BrushEvent(rest[index] + k * delta, delta) for k in range(10)]
    sculptor.apply_brush(Brush(kind, radius=radius, influence=4.0), events)  # as it was then
    moved = sculptor.vertices - rest
    sculptor.undo()
    return moved


def ripples(vertices, faces, displacement, index, eps, rings=(1.5, 2.0, 2.5), bins=32):
    """The wrinkle measure: the displacement's normal component (vertex normals) on rings at
    ``rings`` ε (3D distance) around vertex ``index``, binned by angle about its normal, with
    angular frequencies 0-2 removed (what a smooth pull makes on a curved surface). Returns
    (amplitude, sign changes) of the ring with the largest ripple, the amplitude relative to
    the largest displacement of the stroke."""
    normals = _vertex_normals(vertices, faces)
    normal = normals[index]
    t1 = np.cross(normal, [0.3, 0.5, 0.7])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(normal, t1)
    offsets = vertices - vertices[index]
    distance = np.linalg.norm(offsets, axis=1)
    angle = np.arctan2(offsets @ t2, offsets @ t1)
    along_normal = np.einsum("ij,ij->i", displacement, normals)
    best, measured = (0.0, 0), 0
    for rho in rings:
        near = (np.abs(distance - rho * eps) < 0.12 * eps) & (offsets @ normal > -1.5 * eps)
        slot = ((angle[near] + np.pi) / (2 * np.pi) * bins).astype(int) % bins
        count = np.bincount(slot, minlength=bins)
        if count.min() == 0:  # a ring the mesh samples too coarsely
            continue
        measured += 1
        ring = np.bincount(slot, along_normal[near], bins) / count
        spectrum = np.fft.rfft(ring)
        spectrum[:3] = 0
        ripple = np.fft.irfft(spectrum, bins)
        amplitude = np.abs(ripple).max()
        if amplitude > best[0]:
            best = (amplitude, int(np.sum(np.sign(ripple) != np.sign(np.roll(ripple, 1)))))
    assert measured, "the mesh is too coarse for every ring"
    return best[0] / np.linalg.norm(displacement, axis=1).max(), best[1]


@pytest.fixture(scope="module")
def pebble():
    """The default model, coarser (10,242 vertices), and 6 vertices facing the camera."""
    vertices, faces = default_model(5)
    facing = np.flatnonzero(_vertex_normals(vertices, faces) @ HOME_VIEW > 0.6)
    return vertices, faces, np.random.default_rng(1).choice(facing, 6, replace=False)


def _measure(pebble, material, weights):
    """(wrinkle ripples, grab ripples, wrinkle sign changes, motion / cursor, faces the wrinkle
    stroke turned over) per stroke: 6 centres × 2 directions, the app's default brush radius."""
    vertices, faces, centres = pebble
    radius = Settings().brush.radius
    sculptor = Sculptor(vertices, faces, material=material, degree_weights=weights)
    eps = radius * sculptor.model_size
    up = np.array([0.0, 1.0, 0.0])
    rows = []
    for index in centres:
        for direction in (up, np.cross(up, HOME_VIEW)):
            wrinkle = _stroke(sculptor, "wrinkle_legacy", radius, index, direction)
            grab = _stroke(sculptor, "grab", radius, index, direction)
            amplitude, changes = ripples(vertices, faces, wrinkle, index, eps)
            grab_amplitude, _ = ripples(vertices, faces, grab, index, eps)
            motion = np.linalg.norm(wrinkle, axis=1).max() / eps  # the cursor moved 1 ε
            turned = np.einsum(
                "ij,ij->i", _face_normals(vertices, faces), _face_normals(vertices + wrinkle, faces)
            )
            rows.append((amplitude, grab_amplitude, changes, motion, np.sum(turned <= 0)))
    return np.array(rows)


def test_the_wrinkle_material_ripples_the_default_model_where_grab_does_not(pebble):
    preset = _wrinkle_preset()  # its material; the legacy brush's default weights of l_max 8
    rows = _measure(pebble, preset.material, default_wrinkle_weights(8))
    amplitude, grab, changes, motion, turned = rows.T
    # measured: ripples 0.19 of the largest displacement (median; min 0.055), grab 0.056
    assert np.median(amplitude) >= 0.14, amplitude
    assert np.median(grab) <= 0.09, grab
    assert np.all(amplitude > 2 * grab), (amplitude, grab)
    assert np.median(changes) >= 8, changes  # at least 4 ripples around the ring
    # the grabbed point follows the cursor (the safe falloff bound did not scale the load
    # down): measured 1.0
    assert motion.min() >= 0.95, motion
    assert not turned.any(), turned


def test_the_old_defaults_did_not_show_wrinkles(pebble):
    """The measure above on what shipped before: the 1:30 laminate tilted 20° and weights
    max(1, l/2) (a stroke differed from grab by ~5 %)."""
    laminate = homogenize(make_pattern("layered", 8), bimaterial(contrast=30.0))
    c, s = np.cos(np.radians(20.0)), np.sin(np.radians(20.0))
    old = laminate.rotated(np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]))
    amplitude, grab, *_ = _measure(pebble, old, legacy_wrinkle_weights(8)).T
    assert np.median(amplitude) < 0.12, amplitude  # measured 0.045, grab 0.034
    assert np.median(amplitude) < 2 * np.median(grab)


def test_default_weights_balance_the_radial_terms_at_the_ring():
    gaussian, ring = GaussianRadial(1.0), np.array([WRINKLE_RING])
    for l_max in (2, 6, 8, 12, 60):
        weights = default_wrinkle_weights(l_max)
        assert weights.shape == (l_max + 1,)
        for l, w in enumerate(weights):
            if 2 < l <= WRINKLE_TOP_DEGREE:
                balanced = w * gaussian.radial(l, ring)[0]
                # rounded to 2 decimals (the Falloff panel's)
                wanted = WRINKLE_LEVEL * gaussian.radial(0, ring)[0]
                assert balanced == pytest.approx(wanted, rel=3e-3)
            else:
                assert w == 1.0
        assert weights.max() <= MAX_DEGREE_WEIGHT
    assert np.array_equal(default_wrinkle_weights(8)[4::2], [3.79, 10.67, 35.54])


def _face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


def test_weights_recorded_as_null_keep_their_meaning():
    """Sessions and presets recorded ``degree_weights: null`` for max(1, l/2): None still
    means that, so they replay exactly; new code records its weights explicitly."""
    vertices, faces = icosphere(2)
    material = _wrinkle_preset().material
    assert np.array_equal(legacy_wrinkle_weights(8), np.maximum(1.0, np.arange(9) / 2.0))
    old = Sculptor(vertices, faces, material=material)
    assert np.array_equal(old.settings.wrinkle_weights, legacy_wrinkle_weights(8))
    event = BrushEvent(vertices[5], [0.0, 0.02, 0.01])
    old.apply_brush(Brush("wrinkle_legacy", radius=0.2), [event])
    session = json.loads(json.dumps(old.session()))
    assert session["settings"]["degree_weights"] is None
    replayed = Sculptor.from_session(session, vertices, faces)
    replayed.replay(session["operations"])
    assert np.array_equal(replayed.vertices, old.vertices)
    explicit = Sculptor(
        vertices, faces, material=material, degree_weights=legacy_wrinkle_weights(8)
    )
    explicit.apply_brush(Brush("wrinkle_legacy", radius=0.2), [event])
    assert np.array_equal(explicit.vertices, old.vertices)

    # a preset applied by a script records the weights it applies (the new defaults)
    fresh = Sculptor(vertices, faces)
    _wrinkle_preset().apply(fresh)
    fresh.apply_brush(Brush("wrinkle_legacy", radius=0.2), [event])
    recorded = json.loads(json.dumps(fresh.session()))
    again = Sculptor.from_session(recorded, vertices, faces)
    again.replay(recorded["operations"])
    assert np.array_equal(again.vertices, fresh.vertices)
    assert np.array_equal(
        fresh.settings.wrinkle_weights, default_wrinkle_weights(_wrinkle_preset().l_max)
    )
    # a preset file with null weights applies the new defaults, as the app does
    nameless = _wrinkle_preset()
    fresh = Sculptor(vertices, faces)
    replace(nameless, degree_weights=None).apply(fresh)
    assert np.array_equal(fresh.settings.wrinkle_weights, default_wrinkle_weights(nameless.l_max))
    settings = Settings()
    settings.apply_preset(replace(nameless, degree_weights=None))
    assert np.array_equal(settings.degree_weights, default_wrinkle_weights(nameless.l_max))


if __name__ == "__main__":  # python tests/test_wrinkle.py: the measure, old vs new defaults
    from gogreen_core.shapes import default_model as _model

    _vertices, _faces = _model(5)
    _facing = np.flatnonzero(_vertex_normals(_vertices, _faces) @ HOME_VIEW > 0.6)
    _pebble = (_vertices, _faces, np.random.default_rng(1).choice(_facing, 6, replace=False))
    _laminate = homogenize(make_pattern("layered", 8), bimaterial(contrast=30.0))
    _c, _s = np.cos(np.radians(20.0)), np.sin(np.radians(20.0))
    _old = _laminate.rotated(np.array([[1.0, 0.0, 0.0], [0.0, _c, -_s], [0.0, _s, _c]]))
    _preset = _wrinkle_preset()
    for _name, _material, _weights in [
        ("old: 1:30 laminate, max(1, l/2)", _old, legacy_wrinkle_weights(8)),
        ("new: wrinkle preset, defaults", _preset.material, _preset.degree_weights),
    ]:
        _rows = _measure(_pebble, _material, _weights)
        print(
            f"{_name}: ripples / largest displacement median {np.median(_rows[:, 0]):.3f} "
            f"(min {_rows[:, 0].min():.3f}), grab {np.median(_rows[:, 1]):.3f}; sign changes "
            f"median {np.median(_rows[:, 2]):.0f}; motion / cursor median "
            f"{np.median(_rows[:, 3]):.2f} (min {_rows[:, 3].min():.2f}); faces turned over "
            f"{int(_rows[:, 4].sum())}"
        )
