"""GUI tests of the side panels (pytest-qt). Run with QT_QPA_PLATFORM=offscreen or under Xvfb."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
from gui_helpers import show_widget
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QPalette
from PySide6.QtWidgets import QLabel

import app.panels.homogenization_panel as homogenization_module
from app.panels import FalloffPanel, HomogenizationPanel, MaterialPanel
from app.panels.widgets import is_marked_invalid, zero_cell_colors
from gogreen_core import (
    PATTERNS,
    GaussianRadial,
    KelvinletRadial,
    Material,
    SplineRadial,
    describe_symmetry,
    homogenize,
    make_pattern,
)
from gogreen_core.physics.homogenization import bimaterial
from gogreen_core.sculpt.brushes import fold_weights

RESULT_TIMEOUT_MS = 30000


# ---------------------------------------------------------------------------------------------
# Material panel
# ---------------------------------------------------------------------------------------------
@pytest.fixture
def material_panel(qtbot):
    panel = MaterialPanel()
    qtbot.addWidget(panel)
    panel.resize(400, 800)
    return panel


def test_material_panel_emits_valid_material(qtbot, material_panel):
    panel = material_panel
    assert panel.material == Material.isotropic(1.0, 0.3)
    with qtbot.waitSignal(panel.material_changed, timeout=1000) as blocker:
        panel.set_field("young", 2.5)
    emitted = blocker.args[0]
    assert isinstance(emitted, Material)
    assert emitted == Material.isotropic(2.5, 0.3)
    assert panel.material == emitted
    assert panel.error == ""
    assert panel.invalid_fields() == []


def test_invalid_poisson_shows_error_marks_field_and_keeps_material(qtbot, material_panel):
    panel = material_panel
    panel.show()
    old = panel.material
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_field("poisson", 0.6)
    assert "Poisson ratio ν must lie in (-1, 1/2)" in panel.error  # the panel's name
    assert panel.error_label.isVisible()
    assert panel.invalid_fields() == ["poisson"]
    assert is_marked_invalid(panel.fields["poisson"])
    assert not is_marked_invalid(panel.fields["young"])
    assert panel.material is old
    # A valid value clears the mark and the message, and emits.
    with qtbot.waitSignal(panel.material_changed, timeout=1000) as blocker:
        panel.set_field("poisson", 0.25)
    assert blocker.args[0] == Material.isotropic(1.0, 0.25)
    assert panel.invalid_fields() == [] and panel.error == ""
    assert not panel.error_label.isVisible()


def test_orthotropic_and_inadmissible_poisson_ratios(qtbot, material_panel):
    panel = material_panel
    panel.set_mode("orthotropic")
    expected = Material.orthotropic(
        young=(1.0, 1.0, 3.0), shear=(0.5, 0.5, 0.4), poisson=(0.25, 0.1, 0.1)
    )
    assert panel.material == expected
    old = panel.material
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_field("nu12", 1.5)  # |nu12| must stay below sqrt(E1/E2) = 1
    assert "inadmissible orthotropic Poisson ratio" in panel.error
    assert "nu12" in panel.invalid_fields()
    assert "G23" not in panel.invalid_fields()
    assert panel.material is old


def test_lame_toggle_keeps_the_material(qtbot, material_panel):
    panel = material_panel
    panel.set_field("young", 2.0)
    before = panel.material
    panel.lame_radio.setChecked(True)
    assert panel.fields["lam"].value() == pytest.approx(before.voigt[0, 1])
    assert panel.fields["mu"].value() == pytest.approx(before.voigt[3, 3])
    assert np.allclose(panel.material.voigt, before.voigt, rtol=1e-12)
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_field("mu", -1.0)
    assert panel.invalid_fields() == ["mu"]


def test_voigt_table_is_kept_symmetric(qtbot, material_panel):
    panel = material_panel
    cubic = Material.cubic(3.0, 1.5, 0.4)
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_material(cubic)
    # a cubic material is orthotropic in its axes: shown as such; the table holds it too
    assert panel.mode == "orthotropic" and panel.material is cubic
    assert panel.voigt_table.item(0, 1).text() == "1.5"

    with qtbot.waitSignal(panel.material_changed, timeout=1000) as blocker:
        panel.set_voigt_entry(0, 4, "0.2")
    assert panel.voigt_table.item(4, 0).text() == "0.2"
    entries = panel.voigt_entries()
    assert entries[0, 4] == entries[4, 0] == 0.2
    assert np.array_equal(entries, entries.T)
    assert blocker.args[0].voigt[4, 0] == pytest.approx(0.2)

    # Not positive definite: the table is marked, the material stays.
    old = panel.material
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_voigt_entry(1, 0, "10")
    assert panel.voigt_table.item(0, 1).text() == "10"
    assert "not positive definite" in panel.error
    assert panel.invalid_fields() == ["voigt"]
    assert panel.material is old
    # Not a number.
    with qtbot.assertNotEmitted(panel.material_changed):
        panel.set_voigt_entry(2, 2, "abc")
    assert "not a number" in panel.error
    assert panel.voigt_table.item(2, 2).text() == "3"  # the stored value is put back
    # A valid entry clears the marks.
    with qtbot.waitSignal(panel.material_changed, timeout=1000) as blocker:
        panel.set_voigt_entry(0, 1, "1.4")
    assert blocker.args[0].voigt[1, 0] == pytest.approx(1.4)
    assert panel.invalid_fields() == [] and panel.error == ""


def test_glyph_follows_the_material_and_rotation(qtbot, material_panel):
    panel = material_panel
    glyph = panel.glyph
    low, high = glyph.young_range
    assert high == pytest.approx(low)  # isotropic: a sphere
    revision = glyph.revision
    panel.set_mode("transversely_isotropic")  # E_z = 3 E_p by default
    assert glyph.revision > revision
    low, high = glyph.young_range
    assert high / low == pytest.approx(3.0, rel=0.02)
    axial = panel.material.directional_young(np.array([[0.0, 0.0, 1.0]]))[0]

    radii = glyph.radii
    with qtbot.waitSignal(panel.material_changed, timeout=1000) as blocker:
        panel.rotation.set_angles((90.0, 0.0, 0.0))  # the stiff axis z turns onto y
    rotated = blocker.args[0]
    assert rotated.directional_young(np.array([[0.0, 1.0, 0.0]]))[0] == pytest.approx(axial)
    assert panel.base_material != rotated
    assert not np.allclose(glyph.radii, radii)
    panel.show()
    image = glyph.grab().toImage()
    colors = {image.pixel(x, y) for x in range(0, image.width(), 3) for y in range(image.height())}
    assert len(colors) > 20  # a shaded surface, not a blank widget


# ---------------------------------------------------------------------------------------------
# Homogenization panel
# ---------------------------------------------------------------------------------------------
@pytest.fixture
def homogenization_panel(qtbot):
    panel = HomogenizationPanel()
    qtbot.addWidget(panel)
    panel.auto_compute_check.setChecked(False)
    panel.resize(400, 900)
    yield panel
    panel.cancel()
    panel.wait_for_idle()


def _wait_idle(qtbot, panel):
    qtbot.waitUntil(lambda: not panel.is_busy, timeout=RESULT_TIMEOUT_MS)


def test_pattern_widgets_follow_the_specs(qtbot, homogenization_panel):
    panel = homogenization_panel
    for name, spec in PATTERNS.items():
        panel.set_pattern(name)
        assert list(panel.parameter_widgets) == [p.name for p in spec.parameters]
        defaults = {p.name: p.default for p in spec.parameters}
        assert panel.pattern_parameters() == defaults
        assert np.array_equal(panel.voxel_view.phases, make_pattern(name, 16, **defaults))
    panel.set_pattern("fibers", axis="x", fraction=0.2)
    assert panel.pattern_parameters()["axis"] == "x"
    assert np.array_equal(panel.phases, make_pattern("fibers", 16, axis="x", fraction=0.2))
    # Contrast slider (logarithmic) and field stay in sync.
    panel.contrast_slider.setValue(300)
    assert panel.contrast == pytest.approx(1000.0)
    panel.set_contrast(10.0)
    assert panel.contrast_slider.value() == 100


def test_homogenizes_a_laminate_off_the_gui_thread(qtbot, homogenization_panel, monkeypatch):
    panel = homogenization_panel
    threads = []
    real = homogenization_module.homogenize_detailed

    def recording(*args, **kwargs):
        threads.append(threading.current_thread())
        return real(*args, **kwargs)

    monkeypatch.setattr(homogenization_module, "homogenize_detailed", recording)
    panel.set_pattern("layered", normal="z", fraction=0.5)
    panel.set_contrast(100.0)
    assert not panel.use_button.isEnabled()
    with qtbot.waitSignal(panel.result_ready, timeout=RESULT_TIMEOUT_MS) as blocker:
        panel.compute()
        assert panel.is_busy  # compute() returned at once: the solve runs in the pool
    assert threads and threads[0] is not threading.main_thread()
    assert not panel.is_busy
    assert panel.progress_bar.value() == panel.progress_bar.maximum()
    result = blocker.args[0]
    assert isinstance(result, Material) and result is panel.result
    reference = homogenize(make_pattern("layered", 16, normal="z"), bimaterial(contrast=100.0))
    assert np.allclose(result.voigt, reference.voigt, rtol=1e-8, atol=1e-10)

    symmetry = panel.symmetry
    assert symmetry.symmetry_class == "transversely isotropic" and symmetry.axis == "z"
    assert "transversely isotropic about z" in panel.symmetry_label.text()
    groups = symmetry.groups
    colors = {(i, j): panel.cell_color(i, j).name() for i in range(6) for j in range(6)}
    for (i, j), color in colors.items():
        if groups[i, j] < 0:
            assert color == zero_cell_colors()[0].name()
        for (k, m), other in colors.items():
            assert (color == other) == (groups[i, j] == groups[k, m])
    assert (
        len({c for c in colors.values()} - {zero_cell_colors()[0].name()}) == symmetry.group_count
    )

    assert panel.use_button.isEnabled()
    with qtbot.waitSignal(panel.material_ready, timeout=1000) as ready:
        panel.use_button.click()
    assert ready.args[0] is panel.result


def test_rotating_the_result_needs_no_recompute(qtbot, homogenization_panel):
    panel = homogenization_panel
    panel.set_pattern("layered", normal="z")
    with qtbot.waitSignal(panel.result_ready, timeout=RESULT_TIMEOUT_MS):
        panel.compute()
    unrotated = panel.result
    with qtbot.waitSignal(panel.result_ready, timeout=1000) as blocker:
        panel.rotation.set_angles((90.0, 0.0, 0.0))
    assert not panel.is_busy
    rotated = blocker.args[0]
    assert panel.unrotated_result == unrotated
    assert describe_symmetry(rotated).axis == "y"  # Rx(90°) turns the layer normal onto y
    assert panel.symmetry.symmetry_class == "transversely isotropic"
    assert "pattern axes: transversely isotropic about z" in panel.symmetry_label.text()


def test_newer_request_supersedes_an_older_one(qtbot, homogenization_panel, monkeypatch):
    panel = homogenization_panel
    real = homogenization_module.homogenize_detailed
    outcomes = []

    started = threading.Event()

    def slow(phases, materials, progress=None, **kwargs):
        started.set()
        time.sleep(0.3)  # the second request arrives while the first is here
        try:
            result = real(phases, materials, progress, **kwargs)
        except Exception as exc:
            outcomes.append(type(exc).__name__)
            raise
        outcomes.append("done")
        return result

    monkeypatch.setattr(homogenization_module, "homogenize_detailed", slow)
    results = []
    panel.result_ready.connect(results.append)
    panel.set_pattern("checkerboard")
    panel.set_contrast(10.0)
    panel.compute()
    assert started.wait(10.0)
    panel.set_contrast(1000.0)
    panel.compute()
    _wait_idle(qtbot, panel)
    panel.wait_for_idle()
    assert outcomes == ["Cancelled", "done"]
    assert len(results) == 1
    expected = real(make_pattern("checkerboard", 16), bimaterial(contrast=1000.0)).material
    assert np.allclose(results[0].voigt, expected.voigt, rtol=1e-7)
    assert panel.symmetry.symmetry_class == "cubic"


def test_homogenization_errors_are_shown(qtbot, homogenization_panel, monkeypatch):
    panel = homogenization_panel

    def failing(*args, **kwargs):
        raise RuntimeError("homogenization CG did not converge in 2000 iterations")

    monkeypatch.setattr(homogenization_module, "homogenize_detailed", failing)
    with qtbot.waitSignal(panel.computation_failed, timeout=RESULT_TIMEOUT_MS) as blocker:
        panel.compute()
    assert "did not converge" in blocker.args[0]
    assert "did not converge" in panel.error_label.text()
    assert not panel.error_label.isHidden()
    assert panel.result is None and not panel.use_button.isEnabled()


# ---------------------------------------------------------------------------------------------
# Falloff panel
# ---------------------------------------------------------------------------------------------
@pytest.fixture
def falloff_panel(qtbot):
    return show_widget(qtbot, FalloffPanel(), 400, 900)


def _count(emitter) -> list:
    """The events ``emitter`` (a settings event) emits from now on."""
    calls: list = []
    emitter.connect(calls.append)
    return calls


def test_drag_a_control_point(qtbot, falloff_panel):
    panel = falloff_panel
    editor = panel.editor
    assert editor.active_key == ("R", 0)
    model_changes = _count(panel.settings.events.changed)
    rho, value = editor.control_points()
    index = int(np.searchsorted(rho, 1.0))
    version = panel.radial.version
    before = panel.radial.dimensionless("R", 0, np.array([1.0]))[0]

    start = editor.point_position(index).toPoint()
    qtbot.mousePress(editor, Qt.MouseButton.LeftButton, pos=start)
    assert editor.selected_index == index
    qtbot.mouseMove(editor, pos=start + QPoint(0, -15))
    qtbot.mouseMove(editor, pos=start + QPoint(0, -40))
    qtbot.mouseRelease(editor, Qt.MouseButton.LeftButton, pos=start + QPoint(0, -40))

    new_rho, new_value = editor.control_points()
    assert new_value[index] > value[index] + 0.05
    assert new_rho[index] == pytest.approx(rho[index], abs=0.05)
    assert panel.radial.dimensionless("R", 0, np.array([1.0]))[0] > before
    assert panel.radial.version > version
    assert len(model_changes) >= 2  # live while dragging
    assert panel.radial.eps == 1.0
    # the model hears one drag: a first step, then continued ones (one undo step downstream)
    flags = [c.continued for c in model_changes]
    assert len(flags) >= 2 and flags[0] is False and all(flags[1:])
    assert all(c.names == {"falloff"} for c in model_changes)


def test_point_at_rho_zero_is_pinned_for_l_at_least_1(qtbot, falloff_panel):
    panel = falloff_panel
    panel.curve_combo.setCurrentIndex(
        panel.curve_combo.findText("R₂", Qt.MatchFlag.MatchStartsWith)
    )
    editor = panel.editor
    assert editor.active_key == ("R", 2)
    start = editor.point_position(0).toPoint()
    qtbot.mousePress(editor, Qt.MouseButton.LeftButton, pos=start)
    qtbot.mouseMove(editor, pos=start + QPoint(20, -50))
    qtbot.mouseRelease(editor, Qt.MouseButton.LeftButton, pos=start + QPoint(20, -50))
    rho, value = editor.control_points()
    assert rho[0] == 0.0 and value[0] == 0.0


def test_add_and_remove_points(qtbot, falloff_panel):
    panel = falloff_panel
    editor = panel.editor
    changes = _count(panel.settings.events.falloff)
    count = len(editor.control_points()[0])

    # Double-click on empty space adds a point there.
    target = editor.to_screen(4.5, 1.2)
    qtbot.mouseDClick(editor, Qt.MouseButton.LeftButton, pos=target.toPoint())
    rho, value = editor.control_points()
    assert len(rho) == count + 1
    added = int(np.argmin(np.abs(rho - 4.5)))
    assert rho[added] == pytest.approx(4.5, abs=0.05)
    assert value[added] == pytest.approx(1.2, abs=0.05)
    assert changes

    # Ctrl + click adds too.
    ctrl_target = editor.to_screen(5.5, 0.9).toPoint()
    qtbot.mouseClick(
        editor, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.ControlModifier, ctrl_target
    )
    assert len(editor.control_points()[0]) == count + 2

    # Right click on a point removes it.
    qtbot.mouseClick(editor, Qt.MouseButton.RightButton, pos=editor.point_position(added).toPoint())
    rho, _ = editor.control_points()
    assert len(rho) == count + 1
    assert np.min(np.abs(rho - 4.5)) > 0.05

    # Select + Delete removes the selected point.
    qtbot.mouseClick(editor, Qt.MouseButton.LeftButton, pos=editor.point_position(3).toPoint())
    assert editor.selected_index == 3
    qtbot.keyClick(editor, Qt.Key.Key_Delete)
    assert len(editor.control_points()[0]) == count

    # The point at rho = 0 stays, with an explanation.
    qtbot.mouseClick(editor, Qt.MouseButton.RightButton, pos=editor.point_position(0).toPoint())
    assert len(editor.control_points()[0]) == count
    assert "cannot be removed" in panel.message_label.text()


def test_reset_to_gaussian(qtbot, falloff_panel):
    panel = falloff_panel
    radial_points = panel.editor.control_points()
    panel.editor.add_point_at(2.2, 3.0)
    panel.reset_to_kelvinlet()
    radial = panel.radial
    rho = np.linspace(0.0, 8.0, 17)
    kelvinlet = KelvinletRadial(1.0)
    assert np.allclose(
        radial.dimensionless("R", 0, rho[1:]), kelvinlet.dimensionless("R", 0, rho[1:]), rtol=0.05
    )
    version = radial.version
    changes = _count(panel.settings.events.falloff)
    panel.reset_gaussian_button.click()
    assert len(changes) == 1
    # a new falloff value (immutable), shown by the editor; the Kelvinlet one is unchanged
    assert panel.radial is not radial and panel.editor.radial is panel.radial
    assert np.allclose(
        radial.dimensionless("R", 0, rho[1:]), kelvinlet.dimensionless("R", 0, rho[1:]), rtol=0.05
    )
    radial = panel.radial
    assert radial.version > version
    gaussian = SplineRadial.from_profile(GaussianRadial(1.0), panel.l_max)
    for key in gaussian.curve_keys():
        assert np.allclose(radial.dimensionless(*key, rho), gaussian.dimensionless(*key, rho))
    assert np.array_equal(panel.editor.control_points()[0], radial_points[0])


def test_l_max_and_degree_weights(qtbot, falloff_panel):
    """The degree weights shown are the current brush's: R_l of the even degrees for a grab,
    ℛ_l of the odd ones for an affine brush, the wrinkle brush's pull and folds; edits, l_max
    changes and the buttons reach the settings."""
    panel = falloff_panel
    settings = panel.settings
    settings.brush.kind = "grab"
    assert panel.l_max == 8
    assert panel.degree_weights.title() == "Degree weights: Wide grab brush"
    assert len(panel.weight_spins) == 5  # R0 R2 R4 R6 R8
    assert np.array_equal(panel.weight_grid.values, np.ones(5))
    panel.l_max_spin.setValue(12)
    assert panel.l_max == 12 and len(panel.weight_spins) == 7
    keys = panel.radial.curve_keys()
    assert ("R", 12) in keys and ("dR", 13) in keys
    assert panel.curve_combo.count() == 14  # R0..R12 (7) and ℛ1..ℛ13 (7)

    panel.weight_spins[1].setValue(2.5)  # R2 of the grab brush
    assert settings.weights_for("grab")[2] == 2.5
    panel.l_max_spin.setValue(4)  # fewer degrees: the common ones stay
    assert np.array_equal(settings.weights_for("grab"), [1.0, 1.0, 2.5, 1.0, 1.0, 1.0])
    panel.degree_weights.ones_button.click()
    assert settings.weights_for("grab")[2] == 1.0

    settings.brush.kind = "pinch"  # an affine brush: ℛ1 ℛ3 ℛ5
    assert panel.degree_weights.title() == "Degree weights: Pinch brush"
    assert len(panel.weight_spins) == 3
    panel.weight_spins[0].setValue(16.0)
    assert settings.weights_for("pinch")[1] == 16.0
    assert settings.weights_for("grab")[1] == 1.0  # each brush its own

    panel.l_max_spin.setValue(10)
    settings.brush.kind = "wrinkle"
    fold = panel.degree_weights.fold_combo
    assert fold.isVisibleTo(panel) and fold.currentData() == 8  # the default folds
    fold.setCurrentIndex(fold.findData(10))
    fold.activated.emit(fold.currentIndex())
    assert list(np.flatnonzero(settings.weights_for("wrinkle"))) == [0, 2, 10]
    panel.degree_weights.depth_field.setValue(1.2)
    assert settings.weights_for("wrinkle")[10] == 1.2
    panel.degree_weights.default_button.click()
    assert np.array_equal(settings.weights_for("wrinkle"), fold_weights(10))

    # Loading a falloff: any profile and l_max, one update of the settings
    changes = _count(settings.events.changed)
    panel.set_falloff(KelvinletRadial(0.3), 6)
    # the weights follow l_max
    assert [c.names for c in changes] == [{"falloff", "l_max", "brush_weights"}]
    assert panel.l_max == 6 and panel.radial.eps == 1.0
    rho = np.array([0.5, 1.0, 3.0])
    assert np.allclose(
        panel.radial.dimensionless("dR", 7, rho),
        KelvinletRadial(1.0).dimensionless("dR", 7, rho),
        rtol=1e-3,
    )


def test_curves_made_from_a_gaussian_follow_the_mesh(qtbot, falloff_panel):
    """With the mesh known (ε spanning 14 edges), a reset samples a point every two edges."""
    panel = falloff_panel
    panel.resolution = lambda: 14.0
    panel.reset_to_gaussian()
    rho, _ = panel.radial.curve("R", 0)
    assert len(rho) == 33 and rho[1] == pytest.approx(1 / 7)
    panel.resolution = None
    panel.reset_to_kelvinlet()
    assert len(panel.radial.curve("R", 0)[0]) == 17


def test_curve_selector_and_shown_curves(qtbot, falloff_panel):
    panel = falloff_panel
    editor = panel.editor
    assert editor.visible_keys == [("R", 2), ("R", 0)]
    panel.show_checks[("dR", 1)].setChecked(True)
    panel.show_checks[("R", 2)].setChecked(False)
    assert set(editor.visible_keys) == {("R", 0), ("dR", 1)}
    panel.curve_combo.setCurrentIndex(
        panel.curve_combo.findText("ℛ₃", Qt.MatchFlag.MatchStartsWith)
    )
    assert editor.active_key == ("dR", 3)
    assert editor.visible_keys[-1] == ("dR", 3)
    # Clicking a handle of another shown curve makes it the edited one, and the combo follows.
    point = QPointF(editor.to_screen(*[float(v[2]) for v in panel.radial.curve("dR", 1)]))
    qtbot.mouseClick(editor, Qt.MouseButton.LeftButton, pos=point.toPoint())
    assert editor.active_key == ("dR", 1)
    assert panel.curve_combo.currentText().startswith("ℛ₁")


# ---------------------------------------------------------------------------------------------
# Background work
# ---------------------------------------------------------------------------------------------
def test_background_runner_reports_progress_results_errors_and_cancels(qtbot):
    from app.background import BackgroundRunner
    from gogreen_core.validation import ParameterError

    runner = BackgroundRunner()
    progress, results, failures, cancelled = [], [], [], []
    runner.progress.connect(lambda job, f: progress.append(f))
    runner.finished.connect(lambda job, r: results.append((job, r)))
    runner.failed.connect(lambda job, e: failures.append(e))
    runner.cancelled.connect(cancelled.append)
    release = threading.Event()

    def work(task):
        task.progress(0.5)
        return threading.current_thread() is not threading.main_thread()

    def blocked(task):
        release.wait(10.0)
        task.progress(0.1)  # raises Cancelled: it was cancelled while waiting
        return "never"

    def bad(task):
        raise ParameterError("contrast", "contrast must be > 0")

    first = runner.submit(work)
    slow = runner.submit(blocked)
    failing = runner.submit(bad)
    runner.cancel(slow)
    release.set()
    assert runner.wait(10_000)
    qtbot.waitUntil(lambda: not runner.busy)
    assert results == [(first, True)] and progress == [0.5]
    assert cancelled == [slow]
    assert failures[0].parameter == "contrast"
    assert failing not in [job for job, _ in results]


def test_a_rotation_slider_drag_reaches_the_settings_as_one_continued_edit(qtbot):
    from gogreen_core.interaction.settings import Settings

    settings = Settings()
    panel = MaterialPanel(settings=settings)
    qtbot.addWidget(panel)
    panel.set_mode("orthotropic")  # anisotropic: a rotation changes the material
    changes: list = []
    settings.events.changed.connect(changes.append)
    slider = panel.rotation.sliders[2]
    slider.setSliderDown(True)
    for angle in (10, 20, 30):
        slider.setValue(angle)
    slider.setSliderDown(False)
    assert [c.continued for c in changes] == [False, True, True]
    assert settings.material == panel.material
    panel.rotation.sliders[0].setValue(5)  # a discrete edit after the drag: a new step
    assert changes[-1].continued is False


def test_tiny_voigt_numbers_are_shown_as_zero_and_kept(qtbot, material_panel):
    panel = material_panel
    voigt = np.array(Material.cubic(3.0, 1.5, 0.4).voigt)
    voigt[0, 4] = voigt[4, 0] = 1.6e-12  # round-off of a rotation: not a coefficient
    voigt[1, 5] = voigt[5, 1] = 3e-3  # small but real: shown
    material = Material(voigt)
    panel.set_material(material)
    assert panel.mode == "voigt"
    assert panel.voigt_table.item(0, 4).text() == "0"
    assert panel.voigt_table.item(4, 0).text() == "0"
    assert panel.voigt_table.item(1, 5).text() == "0.003"
    assert panel.voigt_entries()[0, 4] == 1.6e-12  # the stored value keeps full precision
    assert panel.material is material


def test_isotropic_materials_open_in_the_isotropic_mode(qtbot, material_panel):
    panel = material_panel
    soft = Material.isotropic(2.5, 0.42)
    panel.set_material(soft)
    assert panel.mode == "isotropic" and panel.material is soft
    assert panel.fields["young"].value() == pytest.approx(2.5)
    assert panel.fields["poisson"].value() == pytest.approx(0.42)
    panel.set_material(Material.cubic(3.0, 1.5, 0.4))  # orthotropic in its axes
    assert panel.mode == "orthotropic"
    rotated = Material.cubic(3.0, 1.5, 0.4).rotated(
        np.array([[0.6, -0.8, 0], [0.8, 0.6, 0], [0, 0, 1.0]])
    )
    panel.set_material(rotated)  # no type in these axes: the 6x6 table
    assert panel.mode == "voigt"


@pytest.mark.parametrize("name", ["dark", "light"])
def test_captions_errors_and_zero_cells_take_the_theme_colours(qtbot, app_look, name):
    from app.panels.widgets import mark_invalid, set_text_role
    from app.theme import apply_theme, theme

    app = app_look
    colours = apply_theme(app, name)
    panel = FalloffPanel()
    qtbot.addWidget(panel)
    captions = [
        label for label in panel.findChildren(QLabel) if label.property("text_role") == "muted"
    ]
    assert captions, "the falloff panel's captions are muted"
    for label in captions:
        label.ensurePolished()
        assert label.palette().color(label.foregroundRole()).name() == colours.muted_text
    error = QLabel("broken")
    qtbot.addWidget(error)
    set_text_role(error, "error")
    error.ensurePolished()
    assert error.palette().color(error.foregroundRole()).name() == colours.error_text
    with pytest.raises(ValueError, match="role"):
        set_text_role(error, "loud")
    material = MaterialPanel()
    qtbot.addWidget(material)
    material.set_material(Material.cubic(3.0, 1.5, 0.4))
    zero = material.voigt_table.item(0, 3)
    assert zero.foreground().color().name() == colours.muted_text
    mark_invalid(material.voigt_table, True)
    base = material.voigt_table.palette().color(QPalette.ColorRole.Base).name()
    assert base == theme(name).invalid_base


@pytest.mark.parametrize("name", ["dark", "light"])
def test_plots_are_drawn_on_the_themes_paper(qtbot, app_look, name):
    from app.panels.curve_editor import CurveEditor
    from app.panels.glyph import YoungModulusGlyph
    from app.panels.widgets import plot_colors
    from app.theme import apply_theme

    app = app_look
    colours = apply_theme(app, name)
    paper = plot_colors().background.name()
    assert paper == (colours.base if name == "dark" else "#ffffff")
    curves = CurveEditor(SplineRadial.from_profile(GaussianRadial(1.0), 4))
    for plot in (curves, YoungModulusGlyph(Material.isotropic(1.0, 0.3))):
        qtbot.addWidget(plot)
        plot.resize(300, 240)
        image = plot.grab().toImage()
        assert image.pixelColor(4, 4).name() == paper, type(plot).__name__


def test_the_falloff_preview_follows_a_curve_edit(qtbot, falloff_panel):
    panel = falloff_panel
    preview = panel.preview
    panel.settings.brush.kind = "grab"  # the falloff itself (no multi-scale combination)
    assert preview.wait() and preview.kind == "grab"
    before = preview.values.copy()
    assert len(before) == 64 and before.max() == pytest.approx(1.0)
    editor = panel.editor
    rho, _ = editor.control_points()
    start = editor.point_position(int(np.searchsorted(rho, 1.5))).toPoint()
    qtbot.mousePress(editor, Qt.MouseButton.LeftButton, pos=start)
    qtbot.mouseMove(editor, pos=start + QPoint(0, -20))
    qtbot.mouseMove(editor, pos=start + QPoint(0, -50))
    qtbot.mouseRelease(editor, Qt.MouseButton.LeftButton, pos=start + QPoint(0, -50))
    qtbot.waitUntil(lambda: not np.array_equal(preview.values, before), timeout=5_000)
    assert preview.values.max() == pytest.approx(1.0)
    assert (
        preview.values[np.searchsorted(preview.rho, 1.5)]
        > before[np.searchsorted(preview.rho, 1.5)]
    )
    edited = preview.values.copy()
    panel.settings.material = Material.cubic(1.0, 0.5, 0.1)  # the material counts too
    qtbot.waitUntil(lambda: not np.array_equal(preview.values, edited), timeout=5_000)


def test_the_falloff_preview_shows_the_selected_brushes_own_felt_falloff(qtbot, falloff_panel):
    """Not the grab's curve for every brush: each brush's own profile, named in the title (an
    affine brush's centre stays, so its curve starts at 0; a paint brush's is flat within ε)."""
    preview = falloff_panel.preview
    settings = falloff_panel.settings
    curves = {}
    for kind, label in (
        ("grab_local", "Grab"),
        ("grab", "Wide grab"),
        ("scale", "Scale"),
        ("twist", "Twist"),
        ("pinch", "Pinch"),
        ("wrinkle", "Wrinkle"),
        ("smooth", "Smooth"),
    ):
        settings.brush.kind = kind
        assert preview.wait()
        assert preview.kind == kind and preview.title() == f"felt falloff of {label}"
        curves[kind] = preview.values.copy()
        assert curves[kind].max() == pytest.approx(1.0)
    at = {r: int(np.searchsorted(preview.rho, r)) for r in (0.0, 0.9, 3.0)}
    assert curves["scale"][at[0.0]] == 0.0 and curves["twist"][at[0.0]] == 0.0
    assert curves["grab_local"][at[0.0]] == pytest.approx(1.0)
    assert curves["grab"][at[3.0]] > 5 * curves["grab_local"][at[3.0]]  # wide vs local
    assert curves["smooth"][at[0.9]] == pytest.approx(1.0) and curves["smooth"][at[3.0]] == 0.0
    assert not np.allclose(curves["wrinkle"], curves["grab"])
    preview.repaint()


# ---------------------------------------------------------------------------------------------
# Falloff preview: off the GUI thread, latest request wins, tick labels
# ---------------------------------------------------------------------------------------------
def _block_the_worker():
    """Occupy the app's background thread until the returned event is set."""
    from app.background import BackgroundRunner

    runner = BackgroundRunner()
    release, started = threading.Event(), threading.Event()

    def hold(_task):
        started.set()
        release.wait(30)

    runner.submit(hold)
    assert started.wait(10)
    return runner, release


def test_the_falloff_preview_computes_off_the_gui_thread_and_the_latest_request_wins(
    qtbot, falloff_panel, monkeypatch
):
    import app.panels.falloff_preview as falloff_module
    from app.panels.falloff_panel import PreviewComputer, PreviewRequest

    preview = falloff_panel.preview
    assert preview.wait()
    shown = preview.values.copy()
    threads: list[int] = []
    evaluated: list[int] = []
    build, evaluate = PreviewComputer.kernel, falloff_module.felt_falloff

    def recording(self, request):
        threads.append(threading.get_ident())
        return build(self, request)

    def recording_evaluation(kernel, rho, kind):
        evaluated.append(threading.get_ident())
        return evaluate(kernel, rho, kind)

    monkeypatch.setattr(PreviewComputer, "kernel", recording)
    monkeypatch.setattr(falloff_module, "felt_falloff", recording_evaluation)
    runner, release = _block_the_worker()
    try:
        before = (preview.requested, preview.shown)
        materials = [Material.cubic(1.0, 0.5, c44) for c44 in (0.1, 0.2, 0.4)]
        for material in materials:  # three requests while the worker is busy
            falloff_panel.settings.material = material
            preview.recompute()
            assert np.array_equal(preview.values, shown)  # the old curve stays: no flicker
        assert preview.pending
        qtbot.waitUntil(lambda: preview.stale, timeout=5_000)  # dimmed, "updating…"
        preview.repaint()
    finally:
        release.set()
    assert preview.wait() and runner.wait()
    assert not preview.pending and not preview.stale
    # only the latest of the queued requests was computed: its kernel on the worker thread,
    # its 64 samples (numba's parallel driver, like strokes) on the GUI thread
    assert preview.requested - before[0] == 3 and preview.shown - before[1] == 1
    assert len(threads) == 1 and threads[0] != threading.get_ident()
    assert evaluated == [threading.get_ident()]
    rho = np.linspace(0.0, preview.rho_max, len(preview.rho))
    expected = PreviewComputer()(PreviewRequest.of(falloff_panel.settings, rho))
    np.testing.assert_array_equal(preview.values, expected)


def test_a_computing_request_is_shown_and_the_newest_follows(qtbot, falloff_panel, monkeypatch):
    """A request already computing when a newer one is sent still shows its (newer than on
    screen) curve, then the newest replaces it: live updates during a long drag."""
    from app.panels.falloff_panel import PreviewComputer, PreviewRequest

    preview = falloff_panel.preview
    assert preview.wait()
    settings = falloff_panel.settings
    started, release = threading.Event(), threading.Event()
    build = PreviewComputer.kernel

    def slow_first(self, request):
        if not started.is_set():
            started.set()
            release.wait(30)
        return build(self, request)

    monkeypatch.setattr(PreviewComputer, "kernel", slow_first)
    shown = preview.shown
    settings.material = Material.cubic(1.0, 0.5, 0.1)
    preview.recompute()
    assert started.wait(10)  # the first request is computing
    first = PreviewComputer()(PreviewRequest.of(settings, preview.rho))
    settings.material = Material.cubic(1.0, 0.5, 0.4)
    preview.recompute()
    drawn: list[np.ndarray] = []
    preview.update = lambda: drawn.append(preview.values)
    release.set()
    assert preview.wait()
    assert preview.shown - shown == 2
    np.testing.assert_array_equal(drawn[0], first)
    np.testing.assert_array_equal(
        preview.values, PreviewComputer()(PreviewRequest.of(settings, preview.rho))
    )
    assert not np.array_equal(first, preview.values)


@pytest.mark.parametrize("name", ["dark", "light"])
def test_the_falloff_preview_has_tick_labels_in_both_themes(qtbot, app_look, name):
    from app.panels.falloff_panel import FalloffPreview
    from app.panels.widgets import plot_colors
    from app.theme import apply_theme
    from gogreen_core.interaction.settings import Settings

    app = app_look
    apply_theme(app, name)
    preview = FalloffPreview(Settings())
    qtbot.addWidget(preview)
    preview.resize(320, 160)
    preview.recompute()
    assert preview.wait()
    colors = plot_colors()
    image = preview.grab().toImage()
    rect = preview.plot_rect().toRect()
    paper = colors.background

    def text_pixels(x0, y0, x1, y1):
        """Pixels in a box that stand out from the paper like the text colour does."""
        count = 0
        for x in range(max(x0, 0), min(x1, image.width())):
            for y in range(max(y0, 0), min(y1, image.height())):
                c = image.pixelColor(x, y)
                if abs(c.lightness() - paper.lightness()) > 80:
                    count += 1
        return count

    assert abs(colors.text.lightness() - paper.lightness()) > 120  # legible contrast
    # labels left of the plot (0 … 1) and below it (0 … ρ max), and the axis titles
    assert text_pixels(0, rect.top() - 6, rect.left() - 4, rect.bottom() + 6) > 40
    assert text_pixels(rect.left() - 6, rect.bottom() + 4, rect.right() + 6, image.height()) > 80
    assert preview.values is not None and preview.values.max() == pytest.approx(1.0)


def test_degree_weight_labels_and_hint_are_the_selected_brushs(qtbot, falloff_panel):
    """Grab (R0, R2 … even) then Scale (ℛ1, ℛ3 … odd) at l_max 8: as many fields, other
    labels (they kept the grab's); the pinch hint only for the brushes it applies to; the
    wrinkle's fold degrees labelled as folds."""
    panel = falloff_panel
    settings = panel.settings
    grid = panel.degree_weights.grid

    def labels():
        return [label.text() for label in grid.labels]

    settings.brush.kind = "grab_local"
    assert labels() == ["R0", "R2", "R4", "R6", "R8"]
    assert "pinch" not in panel.degree_weights.caption.text()
    settings.brush.kind = "scale"
    assert labels() == ["ℛ1", "ℛ3", "ℛ5", "ℛ7", "ℛ9"]
    assert "pinch" not in panel.degree_weights.caption.text()
    settings.brush.kind = "pinch"
    assert "16 × ℛ₁ makes a pinch local" in panel.degree_weights.caption.text()
    settings.brush.kind = "wrinkle"
    assert labels() == ["R0", "R2", "fold R4", "fold R6", "fold R8"]
    assert "folds" in panel.degree_weights.caption.text()
    settings.brush.kind = "grab"
    assert labels()[0] == "R0" and grid.spins[0].accessibleName() == "Degree weight R0"


def test_unfolding_rotate_the_result_moves_no_field_under_the_pointer(qtbot, homogenization_panel):
    """The walkthrough: expanding "Rotate the result" moved the fields under the cursor, and a
    click meant for one missed ("45" went to the hotkeys)."""
    from PySide6.QtWidgets import QAbstractSpinBox, QPushButton

    panel = homogenization_panel
    panel.resize(420, 1200)
    panel.show()
    qtbot.waitExposed(panel)
    section = panel.rotation_section
    assert not section.expanded
    widgets = [
        w
        for kind in (QAbstractSpinBox, QPushButton)
        for w in panel.findChildren(kind)
        if w.isVisible() and not section.isAncestorOf(w)
    ]
    assert len(widgets) > 5
    before = [w.mapTo(panel, w.rect().topLeft()) for w in widgets]
    section.set_expanded(True)
    qtbot.wait(10)
    assert [w.mapTo(panel, w.rect().topLeft()) for w in widgets] == before
    assert panel.rotation.isVisible()
