"""A widget a test shows is deleted when that test ends (tests/conftest.py), not later inside
the next test's first wait for its window (where Qt would otherwise delete it, beside the new
window). The two tests run in this order: the first leaves a shown widget behind."""

import pytest
import shiboken6
from PySide6.QtWidgets import QWidget

_left_behind: list[QWidget] = []


def test_a_test_shows_a_widget(qtbot):
    widget = QWidget()
    qtbot.addWidget(widget)  # closed by pytest-qt after the test, and deleteLater
    widget.show()
    qtbot.waitExposed(widget)
    _left_behind.append(widget)


def test_the_widget_is_gone_when_the_next_test_begins():
    if not _left_behind:
        pytest.skip("runs after test_a_test_shows_a_widget")
    assert not shiboken6.isValid(_left_behind.pop())
