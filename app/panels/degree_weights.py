"""The Falloff panel's degree weights: ω_l of the current brush, and the wrinkle brush's folds.

Every brush has per-degree weights (:attr:`gogreen_core.EngineSettings.brush_weights`, paper
Fig. 7 and 10): a grab brush's field is Σ ω_l R_l … over the even degrees of G, an affine
brush's Σ ω_l ℛ_l … over the odd degrees of ∇G. The group shows the weights of the brush picked
in the brush bar (the degrees its field has) and edits them; for the wrinkle brush its degrees
≥ 4 are the folds, which the fold degree and depth fields set in one go
(:func:`gogreen_core.sculpt.brushes.fold_weights`). Everything is bound through :mod:`app.bindings`
to the settings: an edit is one undo step, sessions and presets carry it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from PySide6.QtGui import QStandardItemModel
from PySide6.QtWidgets import QComboBox, QGroupBox, QHBoxLayout, QLabel, QPushButton, QVBoxLayout

from app.bindings import bind, bind_view
from app.fields import DecimalField
from app.panels.number_grid import NumberGrid
from app.panels.widgets import set_text_role
from gogreen_core.interaction.settings import Settings
from gogreen_core.sculpt.brushes import (
    FOLD_DEGREES,
    FOLD_DEPTH,
    brush_row,
    brush_type,
    fold_weights,
)

__all__ = ["DegreeWeights", "shown_degrees"]


def shown_degrees(kind: str, l_max: int) -> list[int]:
    """The degrees brush ``kind``'s field has at ``l_max``: even l ≤ l_max (vector brushes,
    R_l), odd l ≤ l_max + 1 (affine brushes, ℛ_l); none for a brush without weights."""
    behaviour = brush_type(kind)
    if not behaviour.weighted:
        return []
    first = 1 if behaviour.is_affine else 0
    return list(range(first, l_max + 2 - (1 - first), 2))


class DegreeWeights(QGroupBox):
    """The degree weights of the current brush (``settings.brush.kind``), bound to
    ``settings.brush_weights``.

    Widgets: ``grid`` (:class:`NumberGrid`, one field per degree the brush has),
    ``ones_button`` (every ω_l at 1, the paper's expansion as it is), ``fold_combo`` and
    ``depth_field`` (the wrinkle brush's folds), ``caption``.
    """

    def __init__(self, settings: Settings) -> None:
        super().__init__("Degree weights")
        self.settings = settings
        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 4, 6, 6)
        self.caption = QLabel()
        self.caption.setWordWrap(True)
        set_text_role(self.caption, "muted")
        layout.addWidget(self.caption)
        self.grid = NumberGrid(
            self._label,
            (-100.0, 100.0),
            columns=2,  # "fold R4" and its field thrice a row are wider than the dock
            name="Degree weight",
            tooltip=lambda index: f"Weight of {self._label(index)} in the brush's field",
        )
        layout.addWidget(self.grid)
        folds = QHBoxLayout()
        self.fold_label = QLabel("Folds: degree")
        folds.addWidget(self.fold_label)
        self.fold_combo = QComboBox()
        self.fold_combo.setToolTip(
            "The SH degree of the folds: more folds around the brush for a higher one (the "
            "material's layers or fibres set where they run; rotate the material to turn them)"
        )
        folds.addWidget(self.fold_combo)
        self.depth_label = QLabel("depth")
        folds.addWidget(self.depth_label)
        self.depth_field = DecimalField(
            0.0,
            2.0,
            decimals=2,
            step=0.1,
            tooltip="How deep the folds go in one event, in units of the cursor motion",
        )
        folds.addWidget(self.depth_field)
        folds.addStretch(1)
        layout.addLayout(folds)
        buttons = QHBoxLayout()
        self.ones_button = QPushButton("All 1")
        self.ones_button.setToolTip("Every degree at weight 1: the field as the paper expands it")
        self.ones_button.clicked.connect(self._all_ones)
        self.default_button = QPushButton("Default")
        self.default_button.setToolTip("The brush's own weights (the wrinkle brush's folds)")
        self.default_button.clicked.connect(
            lambda: self.settings.set_brush_weights(self.kind, None)
        )
        buttons.addWidget(self.ones_button)
        buttons.addWidget(self.default_button)
        buttons.addStretch(1)
        layout.addLayout(buttons)
        self._bind()

    # -- what is shown -----------------------------------------------------------------------
    @property
    def kind(self) -> str:
        return str(self.settings.brush.kind)

    @property
    def degrees(self) -> list[int]:
        """The degrees shown (those the current brush's field has)."""
        return shown_degrees(self.kind, self.settings.l_max)

    def _label(self, index: int) -> str:
        degrees = self.degrees
        if index >= len(degrees):
            return ""
        degree = degrees[index]
        if degree % 2:
            return f"ℛ{degree}"
        return f"fold R{degree}" if self.kind == "wrinkle" and degree >= 4 else f"R{degree}"

    def _omega(self) -> np.ndarray:
        return self.settings.weights_for(self.kind)

    def _show(self, _weights: Mapping | None = None) -> None:
        """The current brush's weights in the grid (the title and caption say whose)."""
        kind = self.kind
        degrees = self.degrees
        row = brush_row(kind)
        self.setTitle(f"Degree weights: {row.label} brush")
        self.setEnabled(bool(degrees))
        if not degrees:
            self.caption.setText("This brush has no Green's function field to weight.")
            self.grid.set_values([])
        else:
            self.caption.setText(f"Each degree's share of the brush's field, {row.weights_hint}")
            self.grid.set_values(self._omega()[degrees])
        wrinkle = kind == "wrinkle"
        for widget in (self.fold_label, self.fold_combo, self.depth_label, self.depth_field):
            widget.setVisible(wrinkle)

    def _folds(self) -> tuple[int | None, float]:
        """(the fold degree, the fold depth) of the wrinkle brush's weights: its largest degree
        ≥ 4 weight and where it is."""
        l_max = self.settings.l_max
        omega = self.settings.weights_for("wrinkle")
        folds = omega[4 : l_max + 1 : 2] if l_max >= 4 else np.zeros(0)
        if not len(folds) or folds.max() <= 0:
            return None, 0.0
        return 4 + 2 * int(np.argmax(folds)), float(folds.max())

    def _show_fold_degree(self, _weights: Mapping | None = None) -> None:
        l_max = self.settings.l_max
        self.fold_combo.clear()
        for degree in FOLD_DEGREES:
            self.fold_combo.addItem(f"{degree}", degree)
            if degree > l_max:  # the folds need the degree: raise l_max first
                index = self.fold_combo.count() - 1
                model = self.fold_combo.model()
                assert isinstance(model, QStandardItemModel)  # a combo box's own model
                item = model.item(index)
                item.setEnabled(False)
        self.fold_combo.setCurrentIndex(self.fold_combo.findData(self._folds()[0]))

    def _show_depth(self, _weights: Mapping | None = None) -> None:
        self.depth_field.setValue(self._folds()[1])

    # -- edits -------------------------------------------------------------------------------
    def _read_grid(self, values: np.ndarray) -> dict:
        omega = self._omega()
        omega[self.degrees] = values
        return {**self.settings.brush_weights, self.kind: tuple(float(w) for w in omega)}

    def _defaults(self) -> None:
        self.settings.set_brush_weights(self.kind, None)

    def _all_ones(self) -> None:
        omega = self._omega()
        omega[self.degrees] = 1.0
        self.settings.set_brush_weights(self.kind, omega.tolist())

    def _with_folds(self, degree: int | None, depth: float) -> dict:
        """The settings' brush weights with the wrinkle brush's folds at ``degree`` and
        ``depth`` (its pull's weights as they are)."""
        omega = self.settings.weights_for("wrinkle")
        if degree is not None:
            folds = fold_weights(self.settings.l_max, int(degree), depth)
            omega[4:] = folds[4:]
        return {**self.settings.brush_weights, "wrinkle": tuple(float(w) for w in omega)}

    def _bind(self) -> None:
        settings = self.settings
        self.depth_field.setKeyboardTracking(False)
        self._bindings = [
            bind(
                settings,
                "brush_weights",
                self.grid,
                self._show,
                self.grid.edited,
                self._read_grid,
                label="Degree weights",
            ),
            bind(
                settings,
                "brush_weights",
                self.fold_combo,
                self._show_fold_degree,
                self.fold_combo.activated,
                lambda _index: self._with_folds(
                    self.fold_combo.currentData(), self._folds()[1] or FOLD_DEPTH
                ),
                label="Fold degree",
            ),
            bind(
                settings,
                "brush_weights",
                self.depth_field,
                self._show_depth,
                self.depth_field.valueChanged,
                lambda depth: self._with_folds(self._folds()[0], depth),
                label="Fold depth",
            ),
        ]
        # the brush or the degrees change what the same weights show
        bind_view(settings.brush, "kind", self, lambda _kind: self._refresh())
        bind_view(settings, "l_max", self, lambda _l_max: self._refresh())

    def _refresh(self) -> None:
        for binding in getattr(self, "_bindings", ()):
            binding.refresh()
