"""The smaller items of an artist's second day (issue 21, list 9), each with a test that fails
without its fix: "Use this material" in sight at the default window size, the voxel preview
turns with the rotation, a fibre composite's E(d) glyph is no needle, the panel shows a
material's type after undo, engine messages use the panels' names, the window opens over most
of the screen. (The Edit menu's Undo / Redo names and "Nothing to undo" are in
test_affine_drags.py.)"""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import show_widget
from PySide6.QtWidgets import QApplication

from app.panels.glyph import MAX_SHAPE_RATIO, YoungModulusGlyph
from app.panels.material_form import rotation_matrix
from app.panels.voxel_preview import VoxelPreview
from gogreen_core import Material, make_pattern
from gogreen_core.files.presets import builtin_presets
from gogreen_core.validation import ParameterError


def test_use_this_material_is_in_sight_at_the_default_window_size(window, qtbot):
    window.resize(1300, 800)  # the size the walkthrough's window had
    window.panel_tabs.setCurrentWidget(window.homogenization_panel)
    button = window.homogenization_panel.use_button
    qtbot.waitUntil(button.isVisible)
    # not clipped by the panel's scroll area: the whole button is on screen
    assert button.visibleRegion().boundingRect() == button.rect()


def _image(qtbot, preview):
    preview.repaint()
    return preview.grab().toImage()


def _differing(a, b) -> float:
    """Share of pixels where one image shows the stiff phase (orange) and the other not
    (the cell's edge lines, drawn in another order, may differ)."""
    from PySide6.QtGui import QColor

    def orange(image, x, y) -> bool:
        color = QColor(image.pixel(x, y))
        return 10 <= color.hsvHue() <= 40 and color.hsvSaturation() > 90

    width, height = a.width(), a.height()
    differ = sum(
        orange(a, x, y) != orange(b, x, y) for x in range(0, width, 2) for y in range(height)
    )
    return differ / (width // 2 * height)


def test_the_voxel_preview_turns_with_the_rotation(qtbot):
    preview = show_widget(qtbot, VoxelPreview(), 240, 220)
    preview.set_phases(make_pattern("checkerboard", 16))
    plain = _image(qtbot, preview)
    preview.set_rotation(rotation_matrix((0.0, 0.0, 45.0)))
    turned = _image(qtbot, preview)
    assert _differing(plain, turned) > 0.05
    # a half turn about z maps the checkerboard cell onto itself: the same picture
    preview.set_rotation(rotation_matrix((0.0, 0.0, 180.0)))
    assert _differing(plain, _image(qtbot, preview)) < 0.01
    preview.set_rotation(np.eye(3))
    assert _differing(plain, _image(qtbot, preview)) == 0.0


def test_the_homogenize_panels_rotation_turns_its_preview(window):
    panel = window.homogenization_panel
    panel.inputs.auto = False
    panel.rotation.set_angles((90.0, 0.0, 30.0))
    np.testing.assert_allclose(panel.voxel_view.rotation, rotation_matrix((90.0, 0.0, 30.0)))


def test_a_fibre_composites_glyph_is_no_needle(qtbot):
    fibre = next(p for p in builtin_presets() if p.name == "Fibre composite").material
    glyph = show_widget(qtbot, YoungModulusGlyph(fibre), 260, 210)
    low, high = glyph.young_range
    assert high / low > 10  # a strong anisotropy: E along the fibres over E across
    radii = glyph.shape_radii
    assert radii.max() == pytest.approx(1.0)
    # a spindle, not a needle (the grid need not sample the very softest direction)
    assert radii.min() == pytest.approx(1.0 / MAX_SHAPE_RATIO, rel=1e-2)
    order = np.argsort(glyph.radii)
    assert np.all(np.diff(radii[order]) >= -1e-12)  # stiffer directions still reach farther
    # a mild anisotropy keeps its true shape, an isotropic material is a sphere
    glyph.set_material(Material.cubic(3.0, 1.5, 0.4))
    assert glyph.shape_exponent == 1.0
    glyph.set_material(Material.isotropic(1.0, 0.3))
    np.testing.assert_allclose(glyph.shape_radii, 1.0)


def test_undo_shows_a_transversely_isotropic_material_as_such(window):
    panel = window.material_panel
    layered = Material.transversely_isotropic(1.0, 4.0, 0.3, 0.1, 0.5)
    window.apply_material(layered)
    assert panel.mode == "transversely_isotropic"
    window.apply_material(Material.isotropic(2.0, 0.2))
    window.undo()
    assert window.model.material == layered
    assert panel.mode == "transversely_isotropic"  # not "Full 6×6"
    assert panel.fields["young_axial"].value() == pytest.approx(4.0)


def test_engine_refusals_use_the_panels_names(window, monkeypatch):
    sculptor = window.document.sculptor

    def refuse(settings, continued=False):
        raise ParameterError("brush_weights", "brush_weights: 99 entries for l_max 8")

    monkeypatch.setattr(sculptor, "apply_settings", refuse)
    window.model.set_brush_weights("grab", np.full(window.model.l_max + 2, 2.0))
    text = window.message_label.text()
    assert text.startswith("Degree weights not applied: Degree weights: 99 entries"), text
    assert "brush_weights" not in text


def test_the_window_opens_over_most_of_the_screen(window):
    from app.main_window import WINDOW_SHARE

    free = QApplication.primaryScreen().availableGeometry()
    assert window.width() == round(WINDOW_SHARE * free.width())
    assert window.height() == round(WINDOW_SHARE * free.height())
    assert WINDOW_SHARE >= 0.9 and free.contains(window.frameGeometry().center())
