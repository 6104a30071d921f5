"""Material panel: pick the elastic material of the sculpting brushes.

Modes: isotropic (Young's modulus E and Poisson ratio ν, or the Lamé parameters λ and μ),
orthotropic (nine engineering constants), transversely isotropic about z (five constants) and
the full symmetric 6×6 Voigt stiffness. The material axes can be rotated by three Euler angles
(extrinsic about x, then y, then z: ``R = Rz(γ) Ry(β) Rx(α)``), applied with
:meth:`gogreen_core.Material.rotated`. A glyph shows the directional Young's modulus.

The panel is a thin view: every material is built by a :class:`gogreen_core.Material`
constructor, whose ValueError (naming the violated condition) is shown in the panel, the
offending fields are marked red, and the last valid material stays in :attr:`material`. The
field to mark comes from :attr:`gogreen_core.validation.ParameterError.parameter` (each field
lists the parameter names that point at it). Given a :class:`gogreen_core.settings.Settings`,
the panel is bound to its ``material`` field both ways.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QBrush
from PySide6.QtWidgets import (
    QButtonGroup,
    QComboBox,
    QFormLayout,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QRadioButton,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from app.panels.glyph import YoungModulusGlyph
from app.panels.widgets import (
    CompactNumberDelegate,
    CompactTable,
    EulerAnglesEditor,
    FitStackedWidget,
    NumberField,
    exact_number_text,
    is_marked_invalid,
    mark_invalid,
    set_text_role,
    zero_cell_colors,
)
from gogreen_core.material import Material
from gogreen_core.settings import ChangeEvent, Settings

__all__ = ["MODES", "TINY_VOIGT", "VOIGT_LABELS", "MaterialPanel", "displayed_voigt"]

#: Mode keys, in the order of the mode selector.
MODES = ("isotropic", "orthotropic", "transversely_isotropic", "voigt")
_MODE_TITLES = {
    "isotropic": "Isotropic",
    "orthotropic": "Orthotropic (axes x, y, z)",
    "transversely_isotropic": "Transversely isotropic (axis z)",
    "voigt": "Full 6×6 stiffness (Voigt)",
}
#: Row/column labels of the Voigt table (order 11, 22, 33, 23, 13, 12; engineering shear).
VOIGT_LABELS = ("11", "22", "33", "23", "13", "12")

_MODULUS_MIN = 1e-12


@dataclass(frozen=True)
class _FieldSpec:
    key: str
    label: str
    default: float
    tooltip: str
    #: Parameter names (ParameterError.parameter) that point at this field.
    keywords: tuple[str, ...]
    minimum: float = -1e300
    maximum: float = 1e300


_ISOTROPIC_EN = (
    _FieldSpec("young", "Young's modulus E", 1.0, "Stiffness E > 0 (any unit)", ("young",)),
    _FieldSpec(
        "poisson",
        "Poisson ratio ν",
        0.3,
        "Lateral contraction, -1 < ν < 1/2 (0.5 = incompressible)",
        ("poisson",),
        -10.0,
        10.0,
    ),
)
_ISOTROPIC_LAME = (
    _FieldSpec("lam", "Lamé λ", 0.576923, "First Lamé parameter; need 3λ + 2μ > 0", ("lam",)),
    _FieldSpec("mu", "Shear modulus μ", 0.384615, "Second Lamé parameter μ > 0", ("mu",)),
)
_ORTHOTROPIC = (
    _FieldSpec("E1", "E1", 1.0, "Young's modulus along x", ("E1",)),
    _FieldSpec("E2", "E2", 1.0, "Young's modulus along y", ("E2",)),
    _FieldSpec("E3", "E3", 3.0, "Young's modulus along z", ("E3",)),
    _FieldSpec("G23", "G23", 0.5, "Shear modulus in the yz plane", ("G23",)),
    _FieldSpec("G13", "G13", 0.5, "Shear modulus in the xz plane", ("G13",)),
    _FieldSpec("G12", "G12", 0.4, "Shear modulus in the xy plane", ("G12",)),
    _FieldSpec("nu12", "ν12", 0.25, "Contraction along y under stress along x", ("nu12",)),
    _FieldSpec("nu13", "ν13", 0.1, "Contraction along z under stress along x", ("nu13",)),
    _FieldSpec("nu23", "ν23", 0.1, "Contraction along z under stress along y", ("nu23",)),
)
_TRANSVERSE = (
    _FieldSpec("young_plane", "In-plane E_p", 1.0, "Young's modulus in the xy plane", ("E1", "E2")),
    _FieldSpec("young_axial", "Axial E_z", 3.0, "Young's modulus along the axis z", ("E3",)),
    _FieldSpec(
        "poisson_plane",
        "In-plane ν_p",
        0.3,
        "In-plane contraction under in-plane stress, |ν_p| < 1",
        ("poisson_plane", "nu12"),
    ),
    _FieldSpec(
        "poisson_axial",
        "Axial ν_pz",
        0.1,
        "Contraction along z under in-plane stress",
        ("poisson_axial", "nu13", "nu23"),
    ),
    _FieldSpec(
        "shear_axial",
        "Axial shear G_z",
        0.5,
        "Shear modulus of planes containing z (G13 = G23)",
        ("G23", "G13"),
    ),
)


def _mentions(message: str, keywords: tuple[str, ...]) -> bool:
    return any(
        re.search(rf"(?<![A-Za-z0-9_]){re.escape(k)}(?![A-Za-z0-9_])", message) for k in keywords
    )


_VOIGT_HINT = (
    "Stiffness C in Voigt order 11, 22, 33, 23, 13, 12 (engineering shear). "
    "Editing (i, j) also sets (j, i); must be positive definite."
)

#: Voigt entries smaller than this fraction of the largest are shown as 0 (round-off).
TINY_VOIGT = 1e-9


def displayed_voigt(voigt: np.ndarray) -> np.ndarray:
    """The (6, 6) Voigt entries as the table shows them: entries with
    ``|x| < TINY_VOIGT · max|C|`` (round-off of rotations and homogenization, e.g. 1.6e-12
    beside 1) as 0; the stored values keep full precision."""
    voigt = np.asarray(voigt, dtype=np.float64)
    scale = float(np.max(np.abs(voigt))) if voigt.size else 0.0
    return np.where(np.abs(voigt) < TINY_VOIGT * scale, 0.0, voigt)


def _isotropic_parameters(material: Material) -> dict[str, float] | None:
    """E, ν, λ and μ of an isotropic ``material`` (to round-off), else None."""
    c = np.asarray(material.voigt, dtype=np.float64)
    scale = float(np.max(np.abs(c)))
    if scale == 0.0 or not np.all(np.isfinite(c)):
        return None
    lam, mu = c[0, 1], c[3, 3]
    expected = np.zeros((6, 6))
    expected[:3, :3] = lam
    expected[np.arange(3), np.arange(3)] = lam + 2 * mu
    expected[np.arange(3, 6), np.arange(3, 6)] = mu
    if np.max(np.abs(c - expected)) > 1e-9 * scale or lam + mu == 0:
        return None
    young = mu * (3 * lam + 2 * mu) / (lam + mu)
    poisson = lam / (2 * (lam + mu))
    return {"young": young, "poisson": poisson, "lam": lam, "mu": mu}


class MaterialPanel(QWidget):
    """Edit a :class:`gogreen_core.Material`; emits ``material_changed(Material)`` on edits.

    Parameters
    ----------
    material : Material, optional
        Initial material (default isotropic E = 1, ν = 0.3, the sculptor's default). Given one,
        the panel opens in the Voigt mode showing it.
    parent : QWidget, optional

    Attributes
    ----------
    fields : dict[str, NumberField]
        Every scalar field by key: ``young``, ``poisson``, ``lam``, ``mu``, ``E1`` … ``nu23``,
        ``young_plane``, ``young_axial``, ``poisson_plane``, ``poisson_axial``, ``shear_axial``.
    mode_combo : QComboBox (data: a key of :data:`MODES`)
    lame_radio : QRadioButton checked when the isotropic mode uses λ, μ.
    voigt_table : QTableWidget, 6×6, kept symmetric.
    rotation : EulerAnglesEditor
    glyph : YoungModulusGlyph
    error_label : QLabel showing the last ValueError (hidden when the input is valid).
    """

    #: Emitted with the new valid Material after each edit that changes it.
    material_changed = Signal(object)

    def __init__(
        self,
        material: Material | None = None,
        parent: QWidget | None = None,
        settings: Settings | None = None,
    ):
        super().__init__(parent)
        self._material = Material.isotropic(1.0, 0.3)
        self._base = self._material  # before the rotation
        self._voigt = np.array(self._material.voigt)
        self._updating = False
        self.fields: dict[str, NumberField] = {}

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 6, 6, 6)
        layout.setSpacing(6)

        self.glyph = YoungModulusGlyph(self._material)
        glyph_box = QGroupBox("Anisotropy: directional Young's modulus E(d)")
        glyph_layout = QVBoxLayout(glyph_box)
        glyph_layout.setContentsMargins(6, 4, 6, 6)
        glyph_layout.addWidget(self.glyph)
        layout.addWidget(glyph_box)

        mode_row = QHBoxLayout()
        mode_row.addWidget(QLabel("Type"))
        self.mode_combo = QComboBox()
        for mode in MODES:
            self.mode_combo.addItem(_MODE_TITLES[mode], mode)
        self.mode_combo.setToolTip("How the stiffness is entered")
        mode_row.addWidget(self.mode_combo, 1)
        layout.addLayout(mode_row)

        self.pages = FitStackedWidget()
        self.pages.addWidget(self._isotropic_page())
        self.pages.addWidget(self._grid_page(_ORTHOTROPIC, columns=3))
        self.pages.addWidget(self._form_page(_TRANSVERSE))
        self.pages.addWidget(self._voigt_page())
        layout.addWidget(self.pages)

        self.error_label = QLabel()
        self.error_label.setWordWrap(True)
        set_text_role(self.error_label, "error")
        self.error_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.error_label.hide()
        layout.addWidget(self.error_label)

        rotation_box = QGroupBox("Rotate material axes (Euler angles)")
        rotation_box.setToolTip(
            "Extrinsic rotations about the fixed x, then y, then z axes: R = Rz(γ) Ry(β) Rx(α)"
        )
        rotation_layout = QVBoxLayout(rotation_box)
        rotation_layout.setContentsMargins(6, 4, 6, 6)
        self.rotation = EulerAnglesEditor()
        self.rotation.changed.connect(self._rebuild)
        rotation_layout.addWidget(self.rotation)
        layout.addWidget(rotation_box)
        layout.addStretch(1)

        self.mode_combo.currentIndexChanged.connect(self._mode_changed)
        self.settings = settings
        self._slider_drag = False
        if settings is not None:
            if material is not None:
                settings.material = material
            if settings.material != self._material:  # else keep the friendlier E, ν page
                self.set_material(settings.material)
            self.material_changed.connect(self._to_model)
            emitter, callback = settings.events.material, self._from_model
            emitter.connect(callback)
            self.destroyed.connect(lambda *_: emitter.disconnect(callback))
        elif material is not None:
            self.set_material(material)

    def _to_model(self, material: Material) -> None:
        # a rotation slider drag is one edit: its steps after the first are "continued"
        dragging = any(slider.isSliderDown() for slider in self.rotation.sliders)
        continued = dragging and self._slider_drag
        self._slider_drag = dragging
        self.settings.set("material", material, continued=continued)

    def _from_model(self, event: ChangeEvent) -> None:
        if event.value != self._material:
            self.set_material(event.value)

    # -- pages -------------------------------------------------------------------------------
    def _make_field(self, spec: _FieldSpec) -> NumberField:
        field = NumberField(spec.default, spec.minimum, spec.maximum, tooltip=spec.tooltip)
        field.valueChanged.connect(self._rebuild)
        self.fields[spec.key] = field
        return field

    def _form_page(self, specs: tuple[_FieldSpec, ...]) -> QWidget:
        page = QWidget()
        form = QFormLayout(page)
        form.setContentsMargins(0, 0, 0, 0)
        for spec in specs:
            label = QLabel(spec.label)
            label.setToolTip(spec.tooltip)
            form.addRow(label, self._make_field(spec))
        return page

    def _grid_page(self, specs: tuple[_FieldSpec, ...], columns: int) -> QWidget:
        page = QWidget()
        grid = QGridLayout(page)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setHorizontalSpacing(4)
        grid.setVerticalSpacing(4)
        for index, spec in enumerate(specs):
            row, col = divmod(index, columns)
            label = QLabel(spec.label)
            label.setToolTip(spec.tooltip)
            label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            grid.addWidget(label, row, 2 * col)
            grid.addWidget(self._make_field(spec), row, 2 * col + 1)
            grid.setColumnStretch(2 * col + 1, 1)
        return page

    def _isotropic_page(self) -> QWidget:
        page = QWidget()
        layout = QVBoxLayout(page)
        layout.setContentsMargins(0, 0, 0, 0)
        toggle = QHBoxLayout()
        self.young_radio = QRadioButton("E, ν")
        self.lame_radio = QRadioButton("Lamé λ, μ")
        self.young_radio.setChecked(True)
        self._param_group = QButtonGroup(self)
        for radio in (self.young_radio, self.lame_radio):
            self._param_group.addButton(radio)
            toggle.addWidget(radio)
        toggle.addStretch(1)
        layout.addLayout(toggle)
        self.isotropic_pages = FitStackedWidget()
        self.isotropic_pages.addWidget(self._form_page(_ISOTROPIC_EN))
        self.isotropic_pages.addWidget(self._form_page(_ISOTROPIC_LAME))
        layout.addWidget(self.isotropic_pages)
        self.lame_radio.toggled.connect(self._lame_toggled)
        return page

    def _voigt_page(self) -> QWidget:
        page = QWidget()
        layout = QVBoxLayout(page)
        layout.setContentsMargins(0, 0, 0, 0)
        table = CompactTable(6, 6)
        table.setHorizontalHeaderLabels(VOIGT_LABELS)
        table.setVerticalHeaderLabels(VOIGT_LABELS)
        table.setToolTip(_VOIGT_HINT)
        # Cells show 4 significant digits (the default dock is too narrow for 6); the items
        # keep the exact value, which the editor and the cell's tool tip show.
        table.setItemDelegate(CompactNumberDelegate(digits=4, parent=table))
        for i in range(6):
            for j in range(6):
                item = QTableWidgetItem()
                item.setTextAlignment(Qt.AlignmentFlag.AlignCenter)
                table.setItem(i, j, item)
        self.voigt_table = table
        self._fill_voigt_table()
        table.itemChanged.connect(self._voigt_item_changed)
        layout.addWidget(table)
        hint = QLabel("Base stiffness before rotation; (i, j) mirrors (j, i).")
        set_text_role(hint, "muted")
        hint.setWordWrap(True)
        layout.addWidget(hint)
        return page

    # -- public API --------------------------------------------------------------------------
    @property
    def material(self) -> Material:
        """The last valid material (rotation applied)."""
        return self._material

    @property
    def base_material(self) -> Material:
        """The last valid material before the rotation of its axes."""
        return self._base

    @property
    def mode(self) -> str:
        """Current mode, a key of :data:`MODES`."""
        return self.mode_combo.currentData()

    def set_mode(self, mode: str) -> None:
        """Switch the input mode (``"isotropic"``, ``"orthotropic"``,
        ``"transversely_isotropic"`` or ``"voigt"``); the Voigt mode starts from the current
        base stiffness, the others from their fields."""
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES} (got {mode!r})")
        self.mode_combo.setCurrentIndex(MODES.index(mode))

    @property
    def error(self) -> str:
        """The message of the last rejected input, or "" when the input is valid."""
        return self.error_label.text() if not self.error_label.isHidden() else ""

    def set_material(self, material: Material, emit: bool = False) -> None:
        """Load ``material`` (rotation reset to zero) in the mode that fits it: an isotropic
        material in the isotropic mode (its E and ν, or λ and μ when that page is shown),
        any other in the Voigt mode.

        Does not emit ``material_changed`` unless ``emit`` (the caller who loads a material
        usually applies it itself).
        """
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material (got {type(material).__name__})")
        isotropic = _isotropic_parameters(material)
        mode = "isotropic" if isotropic is not None else "voigt"
        self._updating = True
        try:
            self._voigt = np.array(material.voigt)
            self._fill_voigt_table()
            if isotropic is not None:
                for key, value in isotropic.items():
                    self.fields[key].blockSignals(True)
                    self.fields[key].setValue(float(value))
                    self.fields[key].blockSignals(False)
            self.rotation.set_angles((0.0, 0.0, 0.0), emit=False)
            self.mode_combo.setCurrentIndex(MODES.index(mode))
            self.pages.setCurrentIndex(MODES.index(mode))
        finally:
            self._updating = False
        self._clear_errors()
        changed = material != self._material
        self._base = self._material = material
        self.glyph.set_material(material)
        if emit and changed:
            self.material_changed.emit(material)

    def set_field(self, key: str, value: float) -> None:
        """Type ``value`` into field ``key`` (as editing it would), switching to its mode."""
        field = self.fields[key]
        if key in ("young", "poisson", "lam", "mu"):
            self.set_mode("isotropic")
            self.lame_radio.setChecked(key in ("lam", "mu"))
        elif key in {s.key for s in _ORTHOTROPIC}:
            self.set_mode("orthotropic")
        else:
            self.set_mode("transversely_isotropic")
        field.setValue(value)

    def set_voigt_entry(self, row: int, col: int, value: float | str) -> None:
        """Edit Voigt cell (row, col) as the user would (text), which also sets (col, row)."""
        self.set_mode("voigt")
        self.voigt_table.item(row, col).setText(str(value))

    def voigt_entries(self) -> np.ndarray:
        """The (6, 6) numbers currently in the Voigt table (base, before rotation)."""
        return self._voigt.copy()

    def invalid_fields(self) -> list[str]:
        """Keys of the fields marked invalid, plus ``"voigt"`` if the table is marked."""
        keys = [k for k, f in self.fields.items() if is_marked_invalid(f)]
        if is_marked_invalid(self.voigt_table):
            keys.append("voigt")
        return keys

    # -- internals ---------------------------------------------------------------------------
    def _fill_voigt_table(self) -> None:
        table = self.voigt_table
        table.blockSignals(True)
        shown = displayed_voigt(self._voigt)
        for i in range(6):
            for j in range(6):
                self._show_voigt_cell(table.item(i, j), shown[i, j])
        table.blockSignals(False)
        mark_invalid(table, False)

    def refresh_colors(self) -> None:
        """Re-colour the Voigt table in the current theme (after a theme switch)."""
        table = self.voigt_table
        table.blockSignals(True)
        for i in range(6):
            for j in range(6):
                item = table.item(i, j)
                zero = item.text() == "0"
                item.setForeground(QBrush(zero_cell_colors()[1]) if zero else QBrush())
        table.blockSignals(False)

    def _show_voigt_cell(self, item: QTableWidgetItem, value: float) -> None:
        """Text of a Voigt cell: ``value`` exactly (the delegate shows it rounded; the editor
        and the tool tip show it whole, with the stored value when round-off is shown as 0);
        zeros muted, the others in the palette's text colour (a default brush, so that they
        follow the theme)."""
        i, j = item.row(), item.column()
        text = exact_number_text(value)
        tip = f"C{VOIGT_LABELS[i]},{VOIGT_LABELS[j]} = {text}"
        stored = float(self._voigt[i, j])
        if stored != value:
            tip += f" (stored {exact_number_text(stored)}: round-off, shown as 0)"
        item.setText(text)
        item.setToolTip(f"{tip}\n{_VOIGT_HINT}")
        item.setBackground(QBrush())
        item.setForeground(QBrush(zero_cell_colors()[1]) if value == 0 else QBrush())

    def _voigt_item_changed(self, item: QTableWidgetItem) -> None:
        i, j = item.row(), item.column()
        text = item.text().strip()
        try:
            value = float(text)
            if not np.isfinite(value):
                raise ValueError
        except ValueError:
            # Keep the table showing numbers: put the stored value back and explain.
            self.voigt_table.blockSignals(True)
            self._show_voigt_cell(item, displayed_voigt(self._voigt)[i, j])
            self.voigt_table.blockSignals(False)
            self._clear_marks()
            mark_invalid(self.voigt_table, True)
            self._show_error(f"C{VOIGT_LABELS[i]},{VOIGT_LABELS[j]}: {text!r} is not a number")
            return
        self._voigt[i, j] = self._voigt[j, i] = value
        self.voigt_table.blockSignals(True)
        for r, c in ((i, j), (j, i)):
            self._show_voigt_cell(self.voigt_table.item(r, c), value)
        self.voigt_table.blockSignals(False)
        self._rebuild()

    def _mode_changed(self, index: int) -> None:
        self.pages.setCurrentIndex(index)
        if self._updating:
            return
        if MODES[index] == "voigt":
            # Continue from the current base stiffness: switching to 6x6 changes nothing.
            self._voigt = np.array(self._base.voigt)
            self._fill_voigt_table()
        self._rebuild()

    def _lame_toggled(self, lame: bool) -> None:
        """Convert the current isotropic material to the other parameter pair, so toggling
        keeps the material: λ = C12, μ = C44, E = 1 / S11, ν = -S12 / S11."""
        self.isotropic_pages.setCurrentIndex(1 if lame else 0)
        try:
            if lame:
                base = Material.isotropic(
                    self.fields["young"].value(), self.fields["poisson"].value()
                )
                values = {"lam": base.voigt[0, 1], "mu": base.voigt[3, 3]}
            else:
                base = Material.from_lame(self.fields["lam"].value(), self.fields["mu"].value())
                s = base.compliance
                values = {"young": 1.0 / s[0, 0], "poisson": -s[0, 1] / s[0, 0]}
        except ValueError:
            values = {}  # invalid pair: keep the other page's values
        for key, value in values.items():
            self.fields[key].blockSignals(True)
            self.fields[key].setValue(float(value))
            self.fields[key].blockSignals(False)
        self._rebuild()

    def _mode_field_keys(self) -> list[str]:
        mode = self.mode
        if mode == "isotropic":
            return ["lam", "mu"] if self.lame_radio.isChecked() else ["young", "poisson"]
        if mode == "orthotropic":
            return [s.key for s in _ORTHOTROPIC]
        if mode == "transversely_isotropic":
            return [s.key for s in _TRANSVERSE]
        return []

    def _build_base(self) -> Material:
        f = {key: field.value() for key, field in self.fields.items()}
        mode = self.mode
        if mode == "isotropic":
            if self.lame_radio.isChecked():
                return Material.from_lame(f["lam"], f["mu"])
            return Material.isotropic(f["young"], f["poisson"])
        if mode == "orthotropic":
            return Material.orthotropic(
                young=(f["E1"], f["E2"], f["E3"]),
                shear=(f["G23"], f["G13"], f["G12"]),
                poisson=(f["nu12"], f["nu13"], f["nu23"]),
            )
        if mode == "transversely_isotropic":
            return Material.transversely_isotropic(
                young_plane=f["young_plane"],
                young_axial=f["young_axial"],
                poisson_plane=f["poisson_plane"],
                poisson_axial=f["poisson_axial"],
                shear_axial=f["shear_axial"],
            )
        return Material.from_voigt(self._voigt)

    def _rebuild(self) -> None:
        if self._updating:
            return
        try:
            base = self._build_base()
            material = (
                base
                if self.rotation.is_identity()
                else base.rotated(self.rotation.rotation_matrix())
            )
        except ValueError as exc:
            self._reject(exc)
            return
        self._clear_errors()
        changed = material != self._material
        self._base, self._material = base, material
        self.glyph.set_material(material)
        if changed:
            self.material_changed.emit(material)

    def _reject(self, exc: ValueError) -> None:
        message = str(exc)
        self._clear_marks()
        if self.mode == "voigt":
            mark_invalid(self.voigt_table, True)
        else:
            keys = self._mode_field_keys()
            specs = {
                s.key: s for s in (*_ISOTROPIC_EN, *_ISOTROPIC_LAME, *_ORTHOTROPIC, *_TRANSVERSE)
            }
            parameter = getattr(exc, "parameter", None)
            if parameter is not None:
                offending = [k for k in keys if parameter in specs[k].keywords]
            else:
                # Transitional: a plain ValueError from a Material constructor not yet raising
                # ParameterError; its message names the parameter as a word.
                offending = [k for k in keys if _mentions(message, specs[k].keywords)]
            for key in offending or keys:
                mark_invalid(self.fields[key], True)
        self._show_error(message)

    def _show_error(self, message: str) -> None:
        self.error_label.setText(f"Not applied: {message}")
        self.error_label.show()

    def _clear_marks(self) -> None:
        for field in self.fields.values():
            if is_marked_invalid(field):
                mark_invalid(field, False)
        if is_marked_invalid(self.voigt_table):
            mark_invalid(self.voigt_table, False)

    def _clear_errors(self) -> None:
        self._clear_marks()
        self.error_label.clear()
        self.error_label.hide()
