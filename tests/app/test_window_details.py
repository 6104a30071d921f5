"""Fixes from a new user's walkthrough, driven with real Qt events where possible: Ctrl+Y
redoes, F12 exports the model without the brush cursor, the cursor hides when the pointer
leaves the viewport or a dialog takes the input, VTK's and pyvista's own keys do nothing,
Save As proposes a file name."""

import numpy as np
from gui_helpers import activate, center_of, drag, hover, shown_viewport
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest

from gogreen_core.mesh.shapes import icosphere


def test_ctrl_y_redoes_like_ctrl_shift_z(window, qtbot):
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    drag(window, center_of(window))
    after = sculptor.vertices.copy()
    assert not np.array_equal(after, before)
    activate(window, qtbot)
    window.viewport.setFocus()
    for redo_key in (
        (Qt.Key.Key_Y, Qt.KeyboardModifier.ControlModifier),
        (Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier),
    ):
        QTest.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
        assert np.array_equal(sculptor.vertices, before)
        QTest.keyClick(window.viewport, *redo_key)
        assert np.array_equal(sculptor.vertices, after), redo_key
        assert np.array_equal(window.viewport.shown_vertices(), after)
    # the keymap overlay and the Redo action's tool tip show both keys
    window.keymap_action.trigger()
    assert any(
        "Ctrl+Y" in line and line.endswith("— Redo") for line in window.keymap_overlay.text_lines()
    )
    assert "Ctrl+Y" in window.redo_action.toolTip()


# -- VTK's and pyvista's own keys never act ------------------------------------------------------
#: Keys VTK's interactor style (p pick outline, s / w surface / wireframe, r reset, e / q exit,
#: f fly to, 3 stereo, j / t / c / a style switches, u user) and pyvista (q close, b pick, v
#: isometric, Shift+C cell picking, Up / Down zoom, plus / minus point size) act on.
VTK_KEYS = [
    (Qt.Key.Key_P, "p"),
    (Qt.Key.Key_S, "s"),
    (Qt.Key.Key_W, "w"),
    (Qt.Key.Key_R, "r"),
    (Qt.Key.Key_F, "f"),
    (Qt.Key.Key_3, "3"),
    (Qt.Key.Key_J, "j"),
    (Qt.Key.Key_T, "t"),
    (Qt.Key.Key_C, "c"),
    (Qt.Key.Key_A, "a"),
    (Qt.Key.Key_U, "u"),
    (Qt.Key.Key_V, "v"),
    (Qt.Key.Key_B, "b"),
    (Qt.Key.Key_Up, ""),
    (Qt.Key.Key_Down, ""),
    (Qt.Key.Key_Plus, "+"),
    (Qt.Key.Key_Minus, "-"),
    (Qt.Key.Key_E, "e"),
    (Qt.Key.Key_Q, "q"),
]


def view_state(vp) -> tuple:
    """What VTK's and pyvista's default keys would change: the camera, the mesh's look, the
    props drawn (a pick outline is a new actor), the interaction style, the window."""
    camera = vp.renderer.GetActiveCamera()
    props = vp.renderer.GetViewProps()
    prop = vp.mesh_actor.GetProperty()
    return (
        camera.GetPosition(),
        camera.GetFocalPoint(),
        camera.GetViewUp(),
        camera.GetViewAngle(),
        prop.GetRepresentation(),
        prop.GetPointSize(),
        prop.GetLineWidth(),
        tuple(props.GetItemAsObject(i) for i in range(props.GetNumberOfItems())),
        vp.iren.interactor.GetInteractorStyle(),
        vp.ren_win.GetStereoRender(),
        vp.render_window is not None,
        vp.isVisible(),
    )


def test_vtk_and_pyvista_keys_do_nothing_in_the_viewport(qtbot):
    vp = shown_viewport(qtbot)
    vertices, faces = icosphere(3)
    vp.set_mesh(vertices, faces)
    vp.render_now()
    QTest.mouseMove(vp, vp.rect().center())  # on the model: a p pick would find it
    before = view_state(vp)
    for key, _text in VTK_KEYS:
        for modifiers in (Qt.KeyboardModifier.NoModifier, Qt.KeyboardModifier.ShiftModifier):
            QTest.keyClick(vp, key, modifiers)
            vp.render_now()
            assert view_state(vp) == before, (key, modifiers)
    # should VTK get key events by another path, its style and pyvista ignore them too
    interactor = vp.iren.interactor
    center = vp.rect().center()
    for key_sym in ("p", "s", "w", "r", "f", "3", "j", "t", "a", "v", "b", "C", "Up", "plus"):
        interactor.SetEventInformationFlipY(center.x(), center.y(), 0, 0, key_sym[0], 0, key_sym)
        interactor.KeyPressEvent()
        interactor.CharEvent()
        interactor.KeyReleaseEvent()
        vp.render_now()
        assert view_state(vp) == before, key_sym


def test_vtk_keys_do_nothing_in_the_window_and_the_apps_keys_still_work(window, qtbot):
    vp = window.viewport
    activate(window, qtbot)
    vp.setFocus()
    QTest.mouseMove(vp, center_of(window))
    before = view_state(vp)
    brush_letters = {"p": "pinch", "s": "scale", "w": "twist", "r": "wrinkle", "t": "grab_triscale"}
    for key, text in VTK_KEYS:
        QTest.keyClick(vp, key)
        vp.render_now()
        assert view_state(vp) == before, key
        if text in brush_letters:  # the app's brush keys
            assert window.model.brush.kind == brush_letters[text]
        if text == "c":  # pin mode on, then off again with the same key
            assert window.tools.mode == "pin"
            QTest.keyClick(vp, key)
            assert window.tools.mode == "brush"
        if text == "f":  # the radius drag, cancelled
            assert vp.value_dragging
            QTest.keyClick(vp, Qt.Key.Key_Escape)
            assert not vp.value_dragging
    assert window.isVisible() and window.document is not None
    QTest.keyClick(vp, Qt.Key.Key_2)
    assert window.model.brush.kind == "grab"  # the wide grab: one key from the local one
    QTest.keyClick(vp, Qt.Key.Key_Z, Qt.KeyboardModifier.ShiftModifier)
    assert window.look.wireframe and window.look.wireframe_action.isChecked()
    QTest.keyClick(vp, Qt.Key.Key_Z, Qt.KeyboardModifier.ShiftModifier)
    assert not window.look.wireframe
    radius = window.model.brush.radius
    QTest.keyClick(vp, Qt.Key.Key_BracketRight)
    assert window.model.brush.radius > radius


# -- F12: the model without the brush cursor -----------------------------------------------------
def png_pixels(path) -> np.ndarray:
    from PySide6.QtGui import QImage

    image = QImage(str(path)).convertToFormat(QImage.Format.Format_RGB888)
    row = image.bytesPerLine()
    data = np.frombuffer(image.constBits(), np.uint8, row * image.height())
    rows = data.reshape(image.height(), row)[:, : 3 * image.width()]
    return rows.reshape(image.height(), image.width(), 3).copy()  # the image's memory goes


def cursor_pixels(pixels: np.ndarray) -> int:
    """Pixels of the brush ring's orange (the model is clay, the background blue-grey)."""
    from app.cursor_overlay import CURSOR_COLOR

    orange = np.array(CURSOR_COLOR) * 255
    return int(np.sum(np.abs(pixels.astype(float) - orange).max(axis=2) < 40))


def test_screenshot_leaves_the_brush_cursor_out_and_restores_it(window, qtbot, tmp_path):
    vp = window.viewport
    hover(window, center_of(window))
    overlay = vp.cursor_overlay
    state, screen = overlay.state, overlay.screen
    # ring and influence ring (the profile is drawn only while F drags the radius)
    assert vp.cursor_visible and state.profile is not None and not overlay.profile_visible
    on_screen = np.ascontiguousarray(vp.screenshot(return_img=True)[:, :, :3])
    assert cursor_pixels(on_screen) > 100  # what the test looks for is there to find
    qtbot.waitUntil(lambda: not vp.render_pending)
    frames = vp.frames
    path = tmp_path / "shot.png"
    assert window.files.save_screenshot(str(path))
    shot = png_pixels(path)
    assert cursor_pixels(shot) == 0
    # restored as it was, drawn again by the next render: one render for the capture, one after
    assert overlay.state is state and vp.cursor_visible
    qtbot.waitUntil(lambda: not vp.render_pending)
    qtbot.wait(50)
    assert vp.frames - frames <= 2
    assert overlay.screen == screen and overlay._ring.actor.GetVisibility()
    assert not overlay.profile_visible and overlay._influence.actor.GetVisibility()
    # the shot is the view with the cursor hidden
    vp.show_cursor(None)
    vp.render_now()
    model_only = np.ascontiguousarray(vp.screenshot(return_img=True)[:, :, :3])
    assert shot.shape == model_only.shape
    assert np.mean(np.any(shot != model_only, axis=2)) < 1e-3


# -- the brush cursor hides when the pointer leaves or a dialog takes the input ------------------
def real_hover(window, qtbot, pos) -> None:
    """A real mouse move over the viewport, then the event loop until the ring is drawn."""
    vp = window.viewport
    QTest.mouseMove(vp, pos + QPoint(2, 2))  # Qt drops a move to where the pointer already is
    QTest.mouseMove(vp, pos)
    qtbot.waitUntil(lambda: vp.cursor_visible, timeout=5000)
    qtbot.waitUntil(lambda: not vp.render_pending, timeout=5000)


def cursor_gone(window) -> bool:
    """Not drawn, and forgotten by the tools (a brush change would otherwise redraw it)."""
    return not window.viewport.cursor_visible and window.tools.cursor.state is None


def test_cursor_hides_when_the_pointer_jumps_out_of_the_view(window, qtbot):
    vp = window.viewport
    activate(window, qtbot)
    real_hover(window, qtbot, center_of(window))
    tab_bar = window.panel_tabs.tabBar()
    QTest.mouseMove(tab_bar, tab_bar.tabRect(1).center())  # one jump onto a panel tab
    qtbot.waitUntil(lambda: cursor_gone(window), timeout=5000)
    qtbot.wait(50)  # a hover or tool step still queued must not bring it back
    assert not vp.cursor_visible
    window.model.brush.radius = 1.5 * window.model.brush.radius  # nor a brush change
    assert not vp.cursor_visible
    real_hover(window, qtbot, center_of(window) + QPoint(5, 5))  # back at the next hover
    status = window.statusBar()
    QTest.mouseMove(status, status.rect().center())  # straight onto the status bar
    qtbot.waitUntil(lambda: cursor_gone(window), timeout=5000)
    real_hover(window, qtbot, center_of(window))


def test_cursor_hides_while_a_modal_dialog_is_open(window, qtbot):
    activate(window, qtbot)
    real_hover(window, qtbot, center_of(window))

    def hidden_while_open(_dialog) -> bool:
        qtbot.waitUntil(lambda: cursor_gone(window), timeout=5000)
        return cursor_gone(window)

    # File > Open: a real modal dialog, answered once the cursor is gone
    seen = answer_file_dialog(window.files.open_dialog, inspect=hidden_while_open)
    assert seen["inspected"] is True
    real_hover(window, qtbot, center_of(window) + QPoint(4, 0))  # back at the next hover


def test_cursor_hides_when_another_window_takes_the_input(window, qtbot):
    from PySide6.QtWidgets import QWidget

    activate(window, qtbot)
    real_hover(window, qtbot, center_of(window))
    other = QWidget()
    qtbot.addWidget(other)
    other.setWindowTitle("another window")
    other.setGeometry(1540, 940, 50, 40)  # away from the pointer: no leave event
    other.show()
    qtbot.waitExposed(other)
    activate(other, qtbot)
    qtbot.waitUntil(lambda: cursor_gone(window), timeout=5000)
    activate(window, qtbot)
    real_hover(window, qtbot, center_of(window) + QPoint(-3, 2))  # back at the next hover


# -- Save As proposes a file name ------------------------------------------------------------------
def answer_file_dialog(open_it, accept: bool = False, inspect=None) -> dict:
    """Call ``open_it`` (which runs a modal QFileDialog) and read what the real dialog proposes:
    its selected file and name filter, and what ``inspect(dialog)`` returns while it is open;
    then cancel it (or accept the proposal), whatever happened."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QFileDialog

    seen = {}

    def answer():
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QFileDialog):
            QTimer.singleShot(20, answer)
            return
        try:
            seen["files"] = dialog.selectedFiles()
            seen["filter"] = dialog.selectedNameFilter()
            if inspect is not None:
                seen["inspected"] = inspect(dialog)
        finally:
            dialog.accept() if accept else dialog.reject()

    QTimer.singleShot(0, answer)
    seen["result"] = open_it()
    return seen


def test_save_as_proposes_the_documents_path_or_untitled_in_the_last_folder(window, tmp_path):
    from pathlib import Path

    opened = Path(window.document.path)
    seen = answer_file_dialog(window.files.save_as_dialog)
    assert [Path(f) for f in seen["files"]] == [opened] and "OBJ" in seen["filter"]
    assert seen["result"] is False  # cancelled: nothing written
    ply = tmp_path / "work" / "statue.ply"
    ply.parent.mkdir()
    assert window.files.save_to(str(ply))
    seen = answer_file_dialog(window.files.save_as_dialog)
    assert [Path(f) for f in seen["files"]] == [ply] and "PLY" in seen["filter"]
    # the default model: untitled.obj in the folder used last, saved there when accepted
    assert window.files.new_document() and window.document.path is None
    seen = answer_file_dialog(window.files.save_as_dialog, accept=True)
    untitled = ply.parent / "untitled.obj"
    assert [Path(f) for f in seen["files"]] == [untitled] and "OBJ" in seen["filter"]
    assert seen["result"] is True and untitled.is_file()
    assert Path(window.document.path) == untitled
