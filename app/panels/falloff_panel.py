"""Falloff panel: edit the brush falloff curves, the SH truncation degree and the brushes'
degree weights.

A view of the falloff fields of :class:`gogreen_core.interaction.settings.Settings` (``falloff``,
``l_max``, ``brush_weights``): the panel owns none of them. The falloff is the settings'
:class:`gogreen_core.SplineRadial` in the dimensionless variable ρ = r/ε (its ε stays 1; the
consumer calls ``with_eps``). Even degrees carry R_l, the falloff of the Green's function G used
by grab brushes; odd degrees carry ℛ_l, used by ∇G and the affine brushes (scale, twist,
pinch). Each edit of the curve editor is a new falloff value; the steps of one point drag after
the first reach the settings as ``continued``, so a whole drag is one undo step in the engine.
Curves of degrees above the current l_max are kept, so lowering and raising l_max restores
them.

Every widget is bound through :mod:`app.bindings`, to the settings or to the panel's
:class:`FalloffView` (which curve is edited, which are shown, the plotted range). A new
widget is one ``bind_*`` call in :meth:`FalloffPanel._bind` (and, for a setting of the panel
alone, one ``Field`` on :class:`FalloffView`).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from app.bindings import bind, bind_choice, bind_spin, bind_view
from app.fields import DecimalField, IntegerField
from app.panels.curve_editor import CurveEditor, curve_color, curve_label
from app.panels.degree_weights import DegreeWeights
from app.panels.falloff_preview import (
    FalloffPreview,
    PreviewComputer,
    PreviewRequest,
    felt_falloff,
)
from app.panels.number_grid import NumberGrid
from app.panels.truncation_readout import TruncationReadout
from app.panels.widgets import scrolled_column, set_text_role
from gogreen_core.interaction.settings import EventedModel, Field, Settings, needed_curves
from gogreen_core.mesh.resolution import spline_abscissae
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, RadialProfile, SplineRadial
from gogreen_core.validation import ParameterError, check_number

__all__ = [
    "L_MAX_RANGE",
    "QUICK_CURVES",
    "FalloffPanel",
    "FalloffPreview",
    "FalloffView",
    "PreviewComputer",
    "PreviewRequest",
    "felt_falloff",
]

#: Range of the truncation degree spin box.
L_MAX_RANGE = (0, 30)
#: Curves with a "show" check box: R₀ and R₂ (shown by default), ℛ₁ and ℛ₃.
QUICK_CURVES = (("R", 0), ("R", 2), ("dR", 1), ("dR", 3))
_DEFAULT_SHOWN = (("R", 0), ("R", 2))
_RHO_MAX_RANGE = (1.0, 50.0)


def _curve_key(_view: EventedModel, name: str, value: Any) -> tuple[str, int]:
    kind, degree = value
    if kind not in ("R", "dR") or int(degree) != degree or degree < 0:
        raise ParameterError(name, f"{name}: a curve (R or dR, degree ≥ 0), got {value!r}")
    return str(kind), int(degree)


def _curve_keys(view: EventedModel, name: str, value: Any) -> tuple[tuple[str, int], ...]:
    return tuple(_curve_key(view, name, key) for key in value)


def _rho_max(_view: EventedModel, name: str, value: Any) -> float:
    return check_number(name, value, low=_RHO_MAX_RANGE[0], high=_RHO_MAX_RANGE[1])


def _show_check(check: QCheckBox, key: tuple[str, int], shown: tuple) -> None:
    check.setChecked(key in shown)


class FalloffView(EventedModel):
    """What the Falloff panel shows, apart from the settings: the curve whose points are
    edited, the curves drawn besides it (of :data:`QUICK_CURVES`) and the right end of the
    plot, in brush radii."""

    active_curve = Field(("R", 0), _curve_key)
    shown_curves = Field(_DEFAULT_SHOWN, _curve_keys)
    rho_max = Field(6.0, _rho_max)


class FalloffPanel(QWidget):
    """Edit the falloff (:attr:`radial`), truncation degree (:attr:`l_max`) and the current
    brush's per-degree weights (:attr:`degree_weights`).

    Parameters
    ----------
    l_max : int, default 8 (the sculptor's default; used when ``settings`` is omitted)
    parent : QWidget, optional
    settings : Settings, optional: the model shown and edited (a private one when omitted)

    Changes reach the settings, whose events tell every listener (the engine, the preview,
    undo); the panel has no signal of its own.

    Widgets (public for scripting and tests): ``editor`` (:class:`CurveEditor`),
    ``curve_combo``, ``show_checks`` ((kind, l) -> QCheckBox), ``rho_max_spin``,
    ``reset_gaussian_button``, ``reset_kelvinlet_button``, ``l_max_spin``, ``truncation``
    (:class:`TruncationReadout`), ``degree_weights`` (:class:`DegreeWeights`: ``weight_grid``
    its grid, ``weight_spins`` its fields), ``message_label``, ``preview``.
    """

    def __init__(
        self, l_max: int = 8, parent: QWidget | None = None, settings: Settings | None = None
    ):
        super().__init__(parent)
        self.settings = settings if settings is not None else Settings(l_max=l_max)
        self._check_l_max(self.settings.l_max)
        self.view = FalloffView()
        #: Brush radii per mesh edge of the sculpted mesh (ε / mean edge length), or None:
        #: set by the window; curves made from a Gaussian are sampled by it.
        self.resolution: Callable[[], float | None] | None = None

        layout = scrolled_column(self)
        self.editor = CurveEditor(self.radial)
        self.editor.setMinimumHeight(240)
        self.editor.setMaximumHeight(400)
        self.editor.message.connect(self._show_message)
        layout.addWidget(self.editor, 1)
        self.preview = FalloffPreview(self.settings)
        layout.addWidget(self.preview)

        hint = QLabel("Drag points · double-click or Ctrl+click adds · right-click or Del removes")
        hint.setWordWrap(True)
        set_text_role(hint, "muted")
        layout.addWidget(hint)
        self.message_label = QLabel()
        self.message_label.setWordWrap(True)
        set_text_role(self.message_label, "error")
        self.message_label.hide()
        layout.addWidget(self.message_label)

        layout.addWidget(self._curves_group())
        layout.addWidget(self._degrees_group())
        self.degree_weights = DegreeWeights(self.settings)
        layout.addWidget(self.degree_weights)
        layout.addStretch(0)
        self._bind()

    # -- construction ------------------------------------------------------------------------
    def _curves_group(self) -> QGroupBox:
        box = QGroupBox("Curves")
        grid = QGridLayout(box)
        grid.setContentsMargins(6, 4, 6, 6)
        grid.setVerticalSpacing(4)
        grid.addWidget(QLabel("Edit"), 0, 0)
        self.curve_combo = QComboBox()
        self.curve_combo.setToolTip(
            "Curve whose points are editable: R_l (even l) shapes grab brushes, "
            "ℛ_l (odd l) the affine brushes (scale, twist, pinch)"
        )
        grid.addWidget(self.curve_combo, 0, 1, 1, 3)
        grid.addWidget(QLabel("Show"), 1, 0)
        checks = QHBoxLayout()
        self.show_checks: dict[tuple[str, int], QCheckBox] = {}
        for key in QUICK_CURVES:
            check = QCheckBox(curve_label(key))
            check.setStyleSheet(f"QCheckBox {{ color: {curve_color(key).name()}; }}")
            check.setToolTip("Grab falloff (G)" if key[0] == "R" else "Affine brushes falloff (∇G)")
            checks.addWidget(check)
            self.show_checks[key] = check
        checks.addStretch(1)
        grid.addLayout(checks, 1, 1, 1, 3)
        grid.addWidget(QLabel("ρ max"), 2, 0)
        self.rho_max_spin = DecimalField(
            *_RHO_MAX_RANGE, decimals=1, step=1.0, tooltip="Right end of the plot, in brush radii"
        )
        grid.addWidget(self.rho_max_spin, 2, 1)
        self.reset_gaussian_button = QPushButton("Reset to Gaussian")
        self.reset_gaussian_button.setToolTip("All curves from the Gaussian load (paper Eq. 13)")
        self.reset_gaussian_button.clicked.connect(self.reset_to_gaussian)
        self.reset_kelvinlet_button = QPushButton("Kelvinlet")
        self.reset_kelvinlet_button.setToolTip(
            "All curves from the regularized Kelvinlet load (de Goes & James 2017)"
        )
        self.reset_kelvinlet_button.clicked.connect(self.reset_to_kelvinlet)
        grid.addWidget(self.reset_gaussian_button, 2, 2)
        grid.addWidget(self.reset_kelvinlet_button, 2, 3)
        grid.setColumnStretch(1, 1)
        return box

    def _degrees_group(self) -> QGroupBox:
        box = QGroupBox("Spherical-harmonic degrees")
        layout = QVBoxLayout(box)
        layout.setContentsMargins(6, 4, 6, 6)
        row = QHBoxLayout()
        row.addWidget(QLabel("Truncation l_max"))
        self.l_max_spin = IntegerField(*L_MAX_RANGE)
        self.l_max_spin.setToolTip(
            "G uses even degrees l ≤ l_max, ∇G odd l ≤ l_max + 1; higher follows strong "
            "anisotropy more closely but costs more per brush step"
        )
        row.addWidget(self.l_max_spin)
        row.addStretch(1)
        layout.addLayout(row)
        self.truncation = TruncationReadout(self.settings)
        layout.addWidget(self.truncation)
        return box

    def _bind(self) -> None:
        """Every widget to its field (the settings' or the view's)."""
        settings, view, editor, combo = self.settings, self.view, self.editor, self.curve_combo
        bind(
            settings,
            "falloff",
            editor,
            self._show_falloff,
            editor.edited,
            lambda: editor.radial,
            label="Falloff",
            dragging=lambda: editor.is_dragging,
            drag_ended=editor.drag_finished,
            revert_on_error=True,
            on_error=self._show_message,
        )
        bind_spin(settings, "l_max", self.l_max_spin, "Truncation l_max")
        bind_view(settings, "l_max", combo, self._fill_curve_combo, block=True)
        bind_view(settings, "l_max", self, self._l_max_shown)
        bind_choice(view, "active_curve", combo, lambda: needed_curves(self.l_max), "Edit")
        bind(
            view,
            "active_curve",
            editor,
            editor.set_active_key,
            editor.active_curve_changed,
            label="Edit",
        )
        for key, check in self.show_checks.items():
            bind(
                view,
                "shown_curves",
                check,
                partial(_show_check, check, key),
                check.toggled,
                lambda on, key=key: self._shown_with(key, on),
                label="Show",
            )
        bind_view(view, "shown_curves", editor, lambda _shown: self._draw_shown_curves())
        bind_spin(view, "rho_max", self.rho_max_spin, "ρ max")
        bind_view(view, "rho_max", editor, editor.set_rho_max)
        bind_view(view, "rho_max", self.preview, self.preview.set_rho_max)
        emitter, callback = settings.events.changed, self._schedule_preview
        emitter.connect(callback)
        bind_view(settings.brush, "kind", self.preview, lambda _kind: self.preview.schedule())
        self.destroyed.connect(lambda *_: emitter.disconnect(callback))

    # -- public API --------------------------------------------------------------------------
    @property
    def radial(self) -> SplineRadial:
        """The edited falloff, the settings' spline (ε = 1; call ``with_eps`` for a radius)."""
        return self.settings.falloff

    @property
    def l_max(self) -> int:
        """Truncation degree of the SH expansion."""
        return self.settings.l_max

    @property
    def weight_grid(self) -> NumberGrid:
        """The current brush's degree weights, one field per degree its field has."""
        return self.degree_weights.grid

    @property
    def weight_spins(self) -> list[DecimalField]:
        """The fields of :attr:`weight_grid`."""
        return self.weight_grid.spins

    def set_l_max(self, l_max: int) -> None:
        """Change the truncation degree: adds Gaussian curves for new degrees (or restores
        earlier edits of them) and gives new degrees each brush's default weights."""
        self.settings.l_max = self._check_l_max(l_max)

    def set_falloff(self, falloff: RadialProfile, l_max: int | None = None) -> None:
        """Load a falloff shape (any profile: a spline's curves are copied, a Gaussian,
        Kelvinlet or multi-scale profile is sampled into curves, one control point every two
        mesh edges when the panel knows the mesh: :attr:`resolution`), optionally with
        ``l_max``. Its ε is ignored."""
        if not isinstance(falloff, RadialProfile):
            raise ValueError(f"falloff must be a RadialProfile (got {type(falloff).__name__})")
        new_l_max = self.l_max if l_max is None else self._check_l_max(l_max)
        if not isinstance(falloff, SplineRadial):
            falloff = SplineRadial.from_profile(falloff, new_l_max, self._abscissae())
        self.settings.update({"l_max": new_l_max, "falloff": falloff})

    def reset_to_gaussian(self) -> None:
        """Replace every curve by the Gaussian load's (the default falloff)."""
        self._reset_to(GaussianRadial(1.0))

    def reset_to_kelvinlet(self) -> None:
        """Replace every curve by the regularized Kelvinlet load's."""
        self._reset_to(KelvinletRadial(1.0))

    # -- internals ---------------------------------------------------------------------------
    @staticmethod
    def _check_l_max(l_max: int) -> int:
        if isinstance(l_max, bool) or int(l_max) != l_max:
            raise ValueError(f"l_max must be an integer (got {l_max!r})")
        l_max = int(l_max)
        if not L_MAX_RANGE[0] <= l_max <= L_MAX_RANGE[1]:
            raise ValueError(
                f"l_max must lie in [{L_MAX_RANGE[0]}, {L_MAX_RANGE[1]}] (got {l_max})"
            )
        return l_max

    def _abscissae(self) -> np.ndarray:
        """Control points (ρ) of a curve sampled for the current mesh and brush: one every two
        edges (:func:`gogreen_core.mesh.resolution.spline_abscissae`), the default 17 when the
        panel does not know the mesh."""
        edges = self.resolution() if self.resolution is not None else None
        return spline_abscissae(edges)

    def _reset_to(self, profile: RadialProfile) -> None:
        rho = self._abscissae()
        samples = SplineRadial.from_profile(profile, self.l_max, rho)
        radial = self.radial.with_curves(samples)
        # Stored curves above l_max are reset too, so raising l_max later stays consistent.
        stale = [k for k in radial.curve_keys() if k not in samples.curve_keys()]
        if stale:
            more = SplineRadial.from_profile(profile, max(degree for _, degree in stale), rho)
            radial = radial.with_curves({key: more.curve(*key) for key in stale})
        self.settings.falloff = radial

    def _show_falloff(self, radial: SplineRadial) -> None:
        self.editor.set_radial(radial)
        self._hide_message()

    def _fill_curve_combo(self, l_max: int) -> None:
        """The curves of ``l_max`` in the combo box, the edited one current."""
        self.curve_combo.clear()
        for key in needed_curves(l_max):
            role = "grab falloff, G" if key[0] == "R" else "affine brushes, ∇G"
            self.curve_combo.addItem(f"{curve_label(key)}   ({role}, l = {key[1]})")
        active = self.view.active_curve
        if active in needed_curves(l_max):
            self.curve_combo.setCurrentIndex(needed_curves(l_max).index(active))

    def _l_max_shown(self, l_max: int) -> None:
        """A new l_max: the edited curve must be one of its curves, the check boxes of the
        curves it lacks are off, the editor draws its shown curves."""
        needed = needed_curves(l_max)
        if self.view.active_curve not in needed:
            self.view.active_curve = ("R", 0)
        for key, check in self.show_checks.items():
            check.setEnabled(key in needed)
        self._draw_shown_curves()

    def _shown_with(self, key: tuple[str, int], on: bool) -> tuple[tuple[str, int], ...]:
        shown = set(self.view.shown_curves) - {key} | ({key} if on else set())
        return tuple(k for k in QUICK_CURVES if k in shown)

    def _draw_shown_curves(self) -> None:
        needed = needed_curves(self.l_max)
        self.editor.set_visible_keys([k for k in self.view.shown_curves if k in needed])

    def _schedule_preview(self, changes) -> None:
        if changes.names & {"material", "falloff", "l_max", "brush_weights"}:
            self.preview.schedule()

    def _show_message(self, text: str | None) -> None:
        if text is None:
            self._hide_message()
            return
        self.message_label.setText(text)
        self.message_label.show()

    def _hide_message(self) -> None:
        self.message_label.clear()
        self.message_label.hide()
