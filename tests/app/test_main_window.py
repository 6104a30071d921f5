"""Main window under Xvfb: load spot, sculpt with simulated mouse drags, undo, save, reopen."""

import numpy as np
import pytest
from gui_helpers import activate, center_of, drag, send
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QMessageBox

from app.main_window import MainWindow
from gogreen_core import Material


def test_opens_and_sculpts_the_shared_spot(window, shared_mesh):
    assert window.files.open_file(str(shared_mesh("spot.obj")))
    assert len(window.document.sculptor.vertices) == 2930  # as listed: seams not split
    before = window.document.sculptor.vertices.copy()
    drag(window, center_of(window))
    assert not np.array_equal(window.document.sculptor.vertices, before)
    window.undo()
    assert np.array_equal(window.document.sculptor.vertices, before)


def test_drag_moves_near_vertices_only_and_undo_restores(window):
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    hit = window.viewport.pick(QPointF(center_of(window)))
    assert hit is not None, "the model should be under the window center"
    drag(window, center_of(window))
    moved = np.linalg.norm(sculptor.vertices - before, axis=1)
    dist = np.linalg.norm(before - hit[0], axis=1)
    assert moved[dist < 0.02 * sculptor.model_size].min() > 0
    assert np.all(moved[dist > 0.6 * sculptor.model_size] == 0)
    assert np.array_equal(window.viewport.shown_vertices(), sculptor.vertices)  # view updated
    assert window.last_step_ms > 0 and "ms" in window.status.step_label.text()
    after = sculptor.vertices.copy()
    window.undo()
    assert np.array_equal(sculptor.vertices, before)
    assert np.array_equal(window.viewport.shown_vertices(), before)  # the rows undo wrote
    window.redo()
    assert np.array_equal(window.viewport.shown_vertices(), after)


def test_invalid_material_keeps_the_old_one(window):
    panel = window.material_panel
    old = window.document.sculptor.settings.material
    panel.set_field("poisson", 0.6)
    assert panel.error
    assert window.document.sculptor.settings.material == old
    panel.set_field("poisson", 0.45)
    assert window.document.sculptor.settings.material == Material.isotropic(1.0, 0.45)


def test_falloff_edit_changes_the_next_deformation(window):
    start = center_of(window)
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    drag(window, start)
    first = sculptor.vertices - before
    window.undo()
    radial = window.falloff_panel.radial
    rho, value = radial.curve("R", 0)
    # a curve edit, as the curve editor makes it: a new falloff value
    window.model.falloff = radial.with_point_moved("R", 0, 2, float(rho[2]), float(value[2]) * 3)
    drag(window, start)
    assert not np.allclose(sculptor.vertices - before, first)


def test_changing_l_max_prepares_its_kernels_in_the_background(window, qtbot):
    assert window.kernel_warmer.wait(120_000)  # the start-up request (the default l_max)
    with qtbot.waitSignal(window.kernel_warmer.ready, timeout=120_000) as ready:
        window.falloff_panel.l_max_spin.setValue(5)
    assert ready.args[0] == 5
    assert window.message_label.text().startswith("l_max = 5 kernels ready")
    # it says what happened: "loaded" from the disk cache (as here, warm), "compiled" when it was
    word = "compiled in" if ready.args[2] else "loaded in"
    assert word in window.message_label.text()
    assert window.document.sculptor.settings.l_max == 5
    assert not window.kernel_warmer.request(5)  # once per degree
    drag(window, center_of(window))  # sculpts with the prepared kernels
    assert window.document.dirty


def test_save_then_reopen_round_trips(window, tmp_path):
    drag(window, center_of(window))
    assert window.document.dirty
    target = tmp_path / "spot_edit.ply"
    assert window.files.save_to(str(target))
    assert not window.document.dirty
    edited = window.document.sculptor.vertices.copy()
    assert window.files.open_file(str(target))
    assert np.array_equal(window.document.sculptor.vertices, edited)
    assert window.files.recent_files()[0].endswith("spot_edit.ply")


def test_bad_file_keeps_the_model(window, tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 1 2\n")
    vertices = window.document.sculptor.vertices.copy()
    assert not window.files.open_file(str(bad))
    assert np.array_equal(window.document.sculptor.vertices, vertices)
    assert "bad.obj" in window.message_label.text()


def test_pin_mode_pins_points_and_dragging_a_pin_moves_it_while_others_stay(window):
    sculptor = window.document.sculptor
    window.brush_bar.constraint_action.setChecked(True)
    vp = window.viewport
    center = center_of(window)
    other = center + QPoint(-60, 40)
    # two clicks pin two surface points
    for pos in (center, other):
        send(vp, QMouseEvent.Type.MouseButtonPress, pos)
        send(vp, QMouseEvent.Type.MouseButtonRelease, pos, buttons=Qt.MouseButton.NoButton)
    pins = sculptor.constraint_points.copy()
    assert len(pins) == 2
    assert np.linalg.norm(pins[0] - pins[1]) > 0
    assert window.viewport.pin_actor is not None
    assert vp.mesh.n_points == len(sculptor.vertices)  # the markers did not replace the model
    # dragging the first pin moves it with the cursor; the second pin stays where it was
    before = sculptor.vertices.copy()
    drag(window, center, steps=4)
    after = sculptor.constraint_points
    assert np.linalg.norm(after[0] - pins[0]) > 1e-3 * sculptor.model_size
    assert np.allclose(after[1], pins[1])
    assert len(after) == 2  # the drag started on a pin: no third pin
    moved = np.linalg.norm(sculptor.vertices - before, axis=1)
    assert moved.max() > 0
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)
    window.undo()  # the whole drag: the surface and the pin go back
    assert np.array_equal(sculptor.vertices, before)
    assert np.array_equal(sculptor.constraint_points, pins)
    window.redo()
    assert np.array_equal(sculptor.constraint_points, after)
    window.clear_constraints()
    assert len(sculptor.constraint_points) == 0


def test_builtin_presets_are_in_the_menu_and_apply(window, tmp_path):
    actions = window.files.presets_menu.actions()
    names = [a.text() for a in actions]
    assert "Rubber (volume preserving)" in names and len(names) >= 5
    rubber = actions[names.index("Rubber (volume preserving)")]
    rubber.trigger()
    assert window.document.sculptor.settings.material == Material.isotropic(1.0, 0.49)
    assert window.material_panel.material == Material.isotropic(1.0, 0.49)
    wrinkle = actions[names.index("Layered sheet wrinkles")]
    wrinkle.trigger()
    assert window.brush_bar.brush.kind == "wrinkle"
    assert (
        not window.document.sculptor.settings.material.voigt[0, 1] == 0.49
    )  # a new, anisotropic one
    # the current settings saved as a preset file load back unchanged
    from gogreen_core import load_preset, save_preset

    path = tmp_path / "mine.json"
    save_preset(window.preset("mine"), path)
    rubber.trigger()
    window.apply_preset(load_preset(path))
    assert window.material_panel.material == load_preset(path).material
    assert window.brush_bar.brush == load_preset(path).brush


def test_view_menu_hides_and_shows_the_panels_and_the_brush_bar(window, qtbot):
    panels, brushes = window.view_actions
    assert (panels.text(), brushes.text()) == ("Panels", "Brush")
    assert panels.isChecked() and brushes.isChecked()
    panels.trigger()
    qtbot.waitUntil(lambda: not window.panels_dock.isVisible())
    assert not panels.isChecked()
    brushes.trigger()
    assert not window.brush_bar.isVisible()
    brushes.trigger()
    panels.trigger()
    assert window.panels_dock.isVisible() and window.brush_bar.isVisible()
    window.panels_dock.close()  # its own close button: the menu entry follows
    qtbot.waitUntil(lambda: not panels.isChecked())


def test_influence_is_a_setting_from_the_brush_bar_to_strokes_sessions_and_presets(window):
    bar, model = window.brush_bar, window.model
    bar.influence.setValue(1.5)  # the widget edits the model...
    assert model.brush.influence == 1.5 and window.brush_bar.brush.influence == 1.5
    model.brush.influence = 2.5  # ...and follows it
    assert bar.influence.value() == 2.5
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    hit = window.viewport.pick(QPointF(center_of(window)))
    drag(window, center_of(window))
    stroke = [op for op in sculptor.session()["operations"] if op["op"] == "stroke"][-1]
    assert stroke["brush"]["influence"] == 2.5  # recorded in the session
    moved = np.linalg.norm(sculptor.vertices - before, axis=1) > 0
    eps = model.brush.brush.eps(sculptor.model_size)
    dist = np.linalg.norm(before - hit[0], axis=1)
    assert moved.any() and dist[moved].max() < 2.5 * eps + 0.1 * sculptor.model_size
    assert window.preset("p").brush.influence == 2.5  # and in presets
    bar.influence.setValue(4.0)
    window.apply_preset(window.preset("p"))
    assert bar.influence.value() == 4.0


def test_panels_and_engine_follow_the_settings_model(window):
    model = window.model
    model.material = Material.isotropic(2.0, 0.4)
    assert window.material_panel.material == Material.isotropic(2.0, 0.4)
    assert window.document.sculptor.settings.material == Material.isotropic(2.0, 0.4)
    model.l_max = 6
    assert window.falloff_panel.l_max_spin.value() == 6
    assert len(window.falloff_panel.weight_spins) == 4  # the grab brush: R0 R2 R4 R6
    assert window.document.sculptor.settings.l_max == 6
    window.falloff_panel.weight_spins[2].setValue(3.0)  # R4
    assert (
        model.weights_for("grab_local")[4]
        == 3.0
        == window.document.sculptor.settings.weights_for("grab_local")[4]
    )
    window.brush_bar.radius.setValue(0.2)
    assert model.brush.radius == 0.2


def test_strokes_wait_for_the_kernels_with_a_message_not_a_freeze(window, monkeypatch):
    ready = window.kernel_warmer.is_ready
    monkeypatch.setattr(window.kernel_warmer, "is_ready", lambda l_max: False)
    before = window.document.sculptor.vertices.copy()
    drag(window, center_of(window))
    assert np.array_equal(window.document.sculptor.vertices, before)
    assert "still compiling" in window.message_label.text()
    assert not window.document.sculptor.in_stroke
    monkeypatch.setattr(window.kernel_warmer, "is_ready", ready)
    drag(window, center_of(window))
    assert window.document.dirty


def test_keys_typed_in_a_number_field_stay_there_and_enter_returns_focus(window, qtbot):
    from PySide6.QtTest import QTest

    activate(window, qtbot)
    field = window.material_panel.fields["young"]
    field.setFocus()
    qtbot.waitUntil(field.hasFocus)
    field.selectAll()
    QTest.keyClick(field, Qt.Key.Key_S)  # a letter in the field, not the Scale brush
    QTest.keyClick(field, Qt.Key.Key_BracketRight)  # nor radius larger
    assert window.model.brush.kind == "grab_local" and window.model.brush.radius == 0.08
    assert field.lineEdit().text() == "s]"
    QTest.keyClick(field, Qt.Key.Key_Escape)  # dropped: the value in effect, keys go home
    assert field.lineEdit().text() == "1"
    qtbot.waitUntil(window.viewport.hasFocus)
    drag(window, center_of(window))
    assert window.document.dirty
    field.setFocus()
    qtbot.waitUntil(field.hasFocus)
    QTest.keyClick(field, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)  # the window's undo
    assert not window.document.dirty
    field.selectAll()
    QTest.keyClicks(field, "2")  # digits go into the field
    QTest.keyClick(field, Qt.Key.Key_Return)
    assert window.model.material == Material.isotropic(2.0, 0.3)
    qtbot.waitUntil(window.viewport.hasFocus)


def test_dark_theme_by_default_light_from_the_view_menu_and_remembered(window, qtbot, tmp_path):
    from PySide6.QtGui import QPalette
    from PySide6.QtWidgets import QApplication

    from app.theme import current_theme, theme

    app = QApplication.instance()
    assert window.look.theme is theme("dark") and current_theme(app) is theme("dark")
    assert app.palette().color(QPalette.ColorRole.Window).name() == theme("dark").window
    bottom, _top = theme("dark").viewport_background
    assert window.viewport.background_color.hex_rgb == bottom
    assert window.look.theme_actions["dark"].isChecked()

    window.look.theme_actions["light"].trigger()
    assert current_theme(app) is theme("light") and window.look.theme_actions["light"].isChecked()
    assert window.viewport.background_color.hex_rgb == theme("light").viewport_background[0]
    assert window.settings.value("theme") == "light"
    again = MainWindow(window.settings)  # the next start
    qtbot.addWidget(again)
    assert again.look.theme is theme("light") and again.look.theme_actions["light"].isChecked()


def test_shortcuts_and_tool_tips_come_from_the_keymap(window):
    from app.keymap import KEYMAP, shortcuts

    keyboard = {entry.action: entry for entry in KEYMAP if not entry.is_gesture}
    bound = window.keymap_actions
    # F / Shift+F drags belong to the viewport's tools, not to window actions
    assert set(keyboard) - set(bound) <= {"radius_drag", "strength_drag"}
    for action_id, action in bound.items():
        assert action.shortcuts() == shortcuts(action_id), action_id
        assert keyboard[action_id].keys[0].replace("Ctrl+", "") in action.toolTip().replace(
            "Ctrl+", ""
        )
    grab = window.brush_bar.kind_actions["grab_local"]
    assert [k.toString() for k in grab.shortcuts()] == ["1", "G"]
    assert grab.toolTip().startswith("Grab: the point under the cursor")
    wide = window.brush_bar.kind_actions["grab"]
    assert [k.toString() for k in wide.shortcuts()] == ["2", "Shift+G"]
    assert [k.toString() for k in window.keymap_action.shortcuts()] == ["?", "F1"]
    keys = window._shortcut_keys()  # what number fields hand over to the window
    assert all(k in keys for k in grab.shortcuts())


def test_brush_and_menu_actions_have_the_projects_icons(window):
    for kind, action in window.brush_bar.kind_actions.items():
        assert action.property("gogreen_icon") == kind and not action.icon().isNull()
    assert window.brush_bar.constraint_action.property("gogreen_icon") == "pin"
    for key, name in {
        "new": "new",
        "open": "open",
        "save": "save",
        "undo": "undo",
        "redo": "redo",
        "screenshot": "screenshot",
        "reset_camera": "home",
        "wireframe": "wireframe",
        "keymap": "help",
    }.items():
        action = window.keymap_actions[key]
        assert action.property("gogreen_icon") == name and not action.icon().isNull(), key


def test_help_menu_f1_and_question_mark_show_the_keymap_over_the_viewport(window, qtbot):
    from PySide6.QtTest import QTest

    activate(window, qtbot)
    overlay = window.keymap_overlay
    assert overlay.parentWidget() is window.viewport and overlay.isHidden()
    window.keymap_action.trigger()
    assert overlay.isVisible() and overlay.geometry() == window.viewport.rect()
    assert "Ctrl+Z — Undo" in overlay.text_lines()
    qtbot.keyClick(overlay, Qt.Key.Key_Escape)
    assert overlay.isHidden()
    qtbot.waitUntil(window.viewport.hasFocus)  # handed back to the view
    QTest.keyClick(window.viewport, Qt.Key.Key_F1)
    assert overlay.isVisible()
    QTest.keyClick(overlay, Qt.Key.Key_F1)
    assert overlay.isHidden()
    qtbot.waitUntil(window.viewport.hasFocus)
    QTest.keyClick(window.viewport, Qt.Key.Key_Question)
    assert overlay.isVisible()


def test_first_run_hint_is_shown_once(window, qtbot):
    from app.main_window import FIRST_RUN_HINT

    assert window.settings.value("keymap_hint_shown", False, type=bool)
    assert "?" in FIRST_RUN_HINT
    again = MainWindow(window.settings)
    qtbot.addWidget(again)
    assert not again.show_first_run_hint()
    assert again.statusBar().currentMessage() != FIRST_RUN_HINT


def test_file_new_opens_the_default_model_after_asking_to_save(window, monkeypatch):
    from app.document import Document

    drag(window, center_of(window))
    assert window.document.dirty
    asked = []
    answer = QMessageBox.StandardButton.Cancel
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: asked.append(a) or answer)
    textured = window.document
    window.new_action.trigger()  # cancelled: the edited model stays
    assert len(asked) == 1 and window.document is textured
    answer = QMessageBox.StandardButton.Discard
    assert [k.toString() for k in window.new_action.shortcuts()] == ["Ctrl+N"]
    assert window.files.new_document()
    default = Document.default()
    assert len(asked) == 2 and window.document.path is None
    assert np.array_equal(window.document.sculptor.vertices, default.sculptor.vertices)
    assert not window.document.dirty
    assert window.files.new_document() and len(asked) == 2  # clean: nothing to ask


def test_screenshot_is_the_viewport_only_and_named_in_the_status_bar(window, tmp_path):
    from PySide6.QtGui import QImage

    path = tmp_path / "shot.png"
    assert window.files.save_screenshot(str(path))
    image = QImage(str(path))
    ratio = window.viewport.devicePixelRatioF()
    size = window.viewport.size()
    assert (image.width(), image.height()) == (
        round(size.width() * ratio),
        round(size.height() * ratio),
    )
    assert image.width() < window.width()  # not the whole window
    corner = image.pixelColor(2, image.height() - 2).name()  # the viewport's background
    assert corner != window.palette().color(window.backgroundRole()).name()
    assert str(path) in window.message_label.text()
    assert not list(tmp_path.glob(".shot.png*"))  # no temporary file left behind
    assert not window.files.save_screenshot(str(tmp_path / "missing" / "shot.png"))
    assert "Cannot write the screenshot" in window.message_label.text()


def test_shading_wireframe_and_orientation_gizmo(window, qtbot):
    from PySide6.QtTest import QTest

    prop = window.viewport.mesh_actor.prop
    assert window.look.shading == "matcap:clay" and window.model.view.shading == "matcap"
    assert not window.look.wireframe and not prop.show_edges
    activate(window, qtbot)
    window.viewport.setFocus()
    QTest.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ShiftModifier)
    assert window.look.wireframe and window.viewport.mesh_actor.prop.show_edges
    window.look.shading_actions["studio"].trigger()
    assert window.look.shading == "studio" and window.settings.value("view/shading") == "studio"
    assert window.model.view.shading == "studio"
    assert window.viewport.mesh_actor.prop.specular > 0.0
    assert len(list(window.viewport.renderer.lights)) > 1  # key, fill, back lights
    window.look.shading_actions["matcap:red_wax"].trigger()
    assert window.model.view.matcap == "red_wax" and window.settings.value("view/matcap")
    assert window.viewport.mesh_actor.GetTexture() is not None  # the matcap's picture
    assert window.files.open_file(str(window.document.path))  # a new mesh actor keeps the look
    prop = window.viewport.mesh_actor.prop
    assert prop.show_edges and prop.specular == 0.0
    assert window.viewport.mesh_actor.GetTexture() is not None
    assert window.look.gizmo_visible
    window.look.gizmo_action.trigger()
    assert not window.look.gizmo_visible
    window.look.gizmo_action.trigger()
    assert window.look.gizmo_visible
    with pytest.raises(ValueError, match="shading"):
        window.look.set_shading("toon")


def test_presets_open_the_material_panel_in_the_mode_of_their_material(window):
    from gogreen_core.files.presets import builtin_presets

    modes = {}
    for preset in builtin_presets():
        window.apply_preset(preset)
        modes[preset.name] = window.material_panel.mode
    assert modes["Soft clay"] == "isotropic"
    assert modes["Wood grain"] == "voigt"
    assert window.material_panel.material == window.model.material


def _curve_drag(qtbot, editor, index: int, dy: int) -> None:
    """Drag control point ``index`` of the active curve ``dy`` pixels in a few mouse steps."""
    start = editor.point_position(index).toPoint()
    qtbot.mousePress(editor, Qt.MouseButton.LeftButton, pos=start)
    for step in (1, 2, 3):
        qtbot.mouseMove(editor, pos=start + QPoint(0, dy * step // 3))
    qtbot.mouseRelease(editor, Qt.MouseButton.LeftButton, pos=start + QPoint(0, dy))


def test_a_curve_drag_is_one_undo_step_restored_exactly_and_redone(window, qtbot):
    activate(window, qtbot)
    window.panel_tabs.setCurrentWidget(window.falloff_panel)
    editor = window.falloff_panel.editor
    qtbot.waitExposed(editor)
    sculptor = window.document.sculptor
    model_curves = window.model.falloff.to_dict()
    engine_curves = sculptor.settings.falloff.to_dict()
    points = editor.control_points()
    depth = len(sculptor.history.undo_labels)
    rho, _ = points
    _curve_drag(qtbot, editor, int(np.searchsorted(rho, 1.0)), -40)
    edited = window.model.falloff.to_dict()
    assert edited != model_curves
    assert sculptor.settings.falloff.to_dict() == edited  # the engine follows every step
    assert len(sculptor.history.undo_labels) == depth + 1  # the whole drag: one step
    assert sculptor.history.undo_labels[-1] == "falloff"

    assert window.undo_action.text() == "&Undo falloff"  # named at once after a settings step
    activate(window, qtbot)
    qtbot.keyClick(editor, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)  # window's undo
    assert window.model.falloff.to_dict() == model_curves
    assert sculptor.settings.falloff.to_dict() == engine_curves
    for shown, before in zip(editor.control_points(), points, strict=True):
        assert np.array_equal(shown, before)  # the editor shows the old curve again
    assert len(sculptor.history.undo_labels) == depth

    window.redo()
    assert window.model.falloff.to_dict() == edited
    assert sculptor.settings.falloff.to_dict() == edited
    window.undo()
    assert window.model.falloff.to_dict() == model_curves


def _folds(window, start: QPoint) -> float:
    """max |wrinkle − wrinkle without folds| / max |wrinkle without folds| of one drag from
    ``start`` (both undone): what the folds add."""
    sculptor = window.document.sculptor
    rest = sculptor.vertices.copy()
    moved = []
    window.model.brush.kind = "wrinkle"
    for flat in (False, True):
        if flat:  # the same brush with its fold weights (degrees ≥ 4) at 0
            omega = window.model.weights_for("wrinkle")
            omega[4:] = 0.0
            window.model.set_brush_weights("wrinkle", omega)
        drag(window, start)
        moved.append(sculptor.vertices - rest)
        window.undo()
        if flat:
            window.undo()  # the weights
    window.model.brush.kind = "grab"
    assert np.array_equal(sculptor.vertices, rest)
    return float(np.abs(moved[0] - moved[1]).max() / np.abs(moved[1]).max())


def test_wrinkle_on_an_isotropic_material_says_so_and_one_click_fixes_it(window, qtbot):
    from app.main_window import material_anisotropy, wrinkle_preset

    sculptor = window.document.sculptor
    old_material, old_settings = window.model.material, sculptor.settings
    assert material_anisotropy(old_material) < 1e-12
    assert window.wrinkle_fix_button.isHidden()
    start = center_of(window)
    iso = _folds(window, start)  # the isotropic material: no folds
    assert iso < 1e-9, iso

    window.model.brush.kind = "wrinkle"
    assert "anisotropic" in window.message_label.text()
    assert "anisotropic" in window.brush_bar.kind_actions["wrinkle"].toolTip()
    assert window.wrinkle_fix_button.isVisible()
    depth = len(sculptor.history.undo_labels)
    qtbot.mouseClick(window.wrinkle_fix_button, Qt.MouseButton.LeftButton)
    preset = wrinkle_preset()
    assert window.model.material == preset.material
    assert sculptor.settings.material == preset.material
    assert material_anisotropy(sculptor.settings.material) > 0.5
    assert len(sculptor.history.undo_labels) == depth + 1  # material and weights: one step
    assert window.wrinkle_fix_button.isHidden()
    assert "anisotropic" not in window.brush_bar.kind_actions["wrinkle"].toolTip()

    # now the folds move the surface (same drag, same start)
    assert window.kernel_warmer.wait(120_000)  # the preset's l_max (strokes wait for it)
    aniso = _folds(window, start)
    assert aniso > 0.1, aniso
    window.model.brush.kind = "wrinkle"
    assert window.wrinkle_fix_button.isHidden()

    window.undo()  # the material step: the old material and weights exactly
    assert window.model.material == old_material
    assert sculptor.settings.material == old_material
    assert sculptor.settings == old_settings
    assert window.wrinkle_fix_button.isVisible()  # wrinkle still picked: offered again


def test_the_active_material_is_named_on_screen_and_stays_when_another_model_opens(
    window, made_textured, tmp_path
):
    """Hidden state no more: the status bar names the material at all times; opening another
    model keeps it (the documented behaviour), named as before."""
    from gogreen_core import builtin_presets

    label = window.status.material_label
    assert label.isVisible() and label.text() == "Material: Soft clay (isotropic, E 1, ν 0.30)"
    fibres = next(p for p in builtin_presets() if p.name == "Fibre composite").material
    window.apply_material(fibres)
    assert label.text().startswith("Material: Fibre composite (fibres along Z, 20.")
    window.material_panel.rotation.set_angles((30.0, 0.0, 0.0))
    assert label.text().endswith("· axes turned 30°, 0°, 0°")
    named = label.text()
    other = tmp_path / "other.obj"
    other.write_bytes(made_textured.path.read_bytes())
    assert window.files.open_file(str(other))
    assert window.document.sculptor.settings.material == window.model.material
    assert label.text() == named and label.isVisible()
