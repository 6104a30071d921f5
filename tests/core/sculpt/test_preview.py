"""The field preview (the paper-controls issue, item 7): what the brush would do for a unit drag,
one field evaluation at the vertices it reaches, so the material shows before the stroke."""

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Material, Sculptor, builtin_presets
from gogreen_core.mesh.shapes import default_model
from gogreen_core.sculpt.preview import field_preview

FIBRES = next(p for p in builtin_presets() if p.name == "Fibre composite").material


@pytest.fixture(scope="module")
def pebble():
    vertices, faces = default_model(4)
    top = int(np.argmax(vertices[:, 1]))
    return vertices, faces, vertices[top]


def test_a_grab_preview_is_one_at_the_cursor_and_what_a_stroke_does(pebble):
    vertices, faces, top = pebble
    sculptor = Sculptor(vertices, faces, material=FIBRES)
    brush = Brush("grab", radius=0.1)
    axis, drag = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    preview = field_preview(sculptor, brush, top, axis, drag)
    centre = int(np.argmax(vertices[:, 1]))
    at_centre = preview.motion[np.flatnonzero(preview.rows == centre)[0]]
    assert at_centre == pytest.approx(1.0, abs=1e-9)  # the grabbed point follows the cursor
    # a tiny stroke moves each vertex by about the preview's field times the motion
    eps = brush.eps(sculptor.model_size)
    step = 1e-4 * eps * drag
    sculptor.apply_brush(brush, [BrushEvent(top, step)])
    moved = np.linalg.norm(sculptor.vertices - vertices, axis=1)[preview.rows] / (1e-4 * eps)
    assert np.abs(moved - preview.motion).max() < 1e-3
    assert np.allclose(preview.motion, np.linalg.norm(preview.velocity, axis=1), rtol=1e-12, atol=0)


def test_the_preview_shows_the_material(pebble):
    """The same grab on an isotropic and a fibre material: the fields differ where a stroke
    would, by a few percent of the motion, mostly in direction (measured: 0.016 in |u|, 0.085 in
    u, of the cursor motion)."""
    vertices, faces, top = pebble
    previews = []
    for material in (Material.isotropic(1.0, 0.3), FIBRES):
        sculptor = Sculptor(vertices, faces, material=material)
        brush = Brush("grab", radius=0.1, influence=4.0)
        previews.append(field_preview(sculptor, brush, top, [0, 0, 1.0], [1.0, 0, 0]))
    iso, fibre = previews
    assert np.array_equal(iso.rows, fibre.rows)
    assert np.linalg.norm(iso.velocity - fibre.velocity, axis=1).max() > 0.05


def test_affine_and_mirrored_previews(pebble):
    vertices, faces, top = pebble
    sculptor = Sculptor(vertices, faces)
    twist = field_preview(sculptor, Brush("twist", radius=0.1), top, [0, 1.0, 0], [1.0, 0, 0])
    assert twist.motion.max() > 0 and len(twist.rows)
    mirrored = Brush("grab", radius=0.05, influence=4.0, symmetry="x")
    side = top + np.array([0.3, 0.0, 0.0])
    preview = field_preview(sculptor, mirrored, side, [0, 0, 1.0], [0, 1.0, 0])
    # the mirror image of the cursor moves too
    image = np.argmin(np.linalg.norm(vertices - side * [-1, 1, 1], axis=1))
    assert image in preview.rows
    assert field_preview(sculptor, mirrored, side, [0, 0, 1.0], [0, 0, 2.0]) is None  # along


def test_wrinkle_and_stretch_previews_and_the_mask(pebble):
    vertices, faces, top = pebble
    sculptor = Sculptor(vertices, faces, material=FIBRES)
    for kind in ("wrinkle", "stretch"):
        preview = field_preview(sculptor, Brush(kind, radius=0.1), top, [0, 0, 1.0], [1.0, 0, 0])
        assert preview is not None and preview.motion.max() > 0
    assert field_preview(sculptor, Brush("smooth"), top, [0, 0, 1.0], [1.0, 0, 0]) is None
    brush = Brush("grab", radius=0.1, influence=4.0)
    free = field_preview(sculptor, brush, top, [0, 0, 1.0], [1.0, 0, 0])
    sculptor.mask.invert()  # all held: a stroke would move nothing, nor does the preview
    held = field_preview(sculptor, brush, top, [0, 0, 1.0], [1.0, 0, 0])
    assert np.array_equal(held.rows, free.rows) and not held.motion.any()
