"""Fixes from a new user's walkthrough, driven with real Qt events where possible: Ctrl+Y
redoes, F12 exports the model without the brush cursor, the cursor hides when the pointer
leaves the viewport or a dialog takes the input, VTK's and pyvista's own keys do nothing,
Save As proposes a file name."""

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from gogreen_core.shapes import icosphere
from tests.test_app import activate, center_of, drag


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
    from tests.test_viewport import _shown_viewport

    vp = _shown_viewport(qtbot)
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
    assert window.model.brush.kind == "grab_biscale"
    QTest.keyClick(vp, Qt.Key.Key_Z, Qt.KeyboardModifier.ShiftModifier)
    assert window.wireframe and window.wireframe_action.isChecked()
    QTest.keyClick(vp, Qt.Key.Key_Z, Qt.KeyboardModifier.ShiftModifier)
    assert not window.wireframe
    radius = window.model.brush.radius
    QTest.keyClick(vp, Qt.Key.Key_BracketRight)
    assert window.model.brush.radius > radius
