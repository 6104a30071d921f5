"""How accurate the current l_max is for the current material (paper Fig. 9), in the Falloff
panel: δ(l_max) computed off the GUI thread whenever the material changes
(:func:`gogreen_core.field.truncation.truncation_errors`, 0.2–1 s), the l_max that keeps it under
0.1 %, and a button that picks it."""

from __future__ import annotations

from PySide6.QtWidgets import QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from app.background import BackgroundRunner, Task
from app.bindings import bind_view
from app.panels.widgets import set_text_role
from gogreen_core.field.truncation import DEFAULT_TOLERANCE, TruncationReport, truncation_errors
from gogreen_core.interaction.settings import Settings
from gogreen_core.physics.material import Material

__all__ = ["TruncationReadout"]

#: The largest l_max measured (the readout's reference goes 16 above it).
MAX_DEGREE = 20


class TruncationReadout(QWidget):
    """The truncation error of ``settings.material`` at ``settings.l_max``.

    Widgets: ``label`` (the summary, e.g. "l_max 8: error 0.18 % of the displacement; l_max 10
    brings it under 0.1 %"), ``use_button`` ("Use l_max 10", hidden when l_max is already the
    suggestion). :attr:`report` is the latest :class:`TruncationReport` (None while computing).
    """

    def __init__(self, settings: Settings, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.settings = settings
        self.report: TruncationReport | None = None
        self._material: Material | None = None
        # not a child of the readout: a job still running when the readout is deleted reports
        # to a live runner, whose connections to the deleted readout Qt has dropped
        self.runner = BackgroundRunner()
        self.runner.finished.connect(self._computed)
        self.runner.failed.connect(self._failed)
        self.destroyed.connect(self.runner.cancel)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 2, 0, 0)
        self.label = QLabel()
        self.label.setWordWrap(True)
        set_text_role(self.label, "muted")
        self.label.setToolTip(
            "The relative error of the truncated expansion of G within 6 ε (paper Fig. 9), "
            "measured against the expansion 16 degrees higher; isotropic materials are exact "
            "from l_max 2"
        )
        layout.addWidget(self.label)
        row = QHBoxLayout()
        self.use_button = QPushButton()
        self.use_button.setToolTip("Set l_max to the suggestion (an undo step)")
        self.use_button.clicked.connect(self._use_suggestion)
        self.use_button.hide()
        row.addWidget(self.use_button)
        row.addStretch(1)
        layout.addLayout(row)
        bind_view(settings, "material", self, self._material_changed)
        bind_view(settings, "l_max", self, lambda _l_max: self._show())

    def _material_changed(self, material: Material) -> None:
        if material == self._material:
            return
        self._material, self.report = material, None
        self._show()
        # a newer material cancels the older computation
        self.runner.submit(lambda task: _measure(material, task), supersede=True)

    def _computed(self, _job: int, report: TruncationReport) -> None:
        self.report = report
        self._show()

    def _failed(self, _job: int, error: BaseException) -> None:
        self.label.setText(f"Truncation error not measured: {error}")

    def _show(self) -> None:
        report = self.report
        if report is None:
            self.label.setText("Measuring the truncation error of this material…")
            self.use_button.hide()
            return
        l_max = self.settings.l_max
        self.label.setText(report.summary(l_max))
        best = report.suggested()
        self.use_button.setText(f"Use l_max {best}")
        # more accurate, or as accurate and faster
        useful = report.error(l_max) > DEFAULT_TOLERANCE or best < l_max - 1
        self.use_button.setVisible(best != l_max and useful)

    def _use_suggestion(self) -> None:
        if self.report is not None:
            self.settings.l_max = self.report.suggested()


def _measure(material: Material, task: Task) -> TruncationReport:
    return truncation_errors(
        material,
        MAX_DEGREE,
        progress=lambda done, total: task.progress(done / total),
    )
