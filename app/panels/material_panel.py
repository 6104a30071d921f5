"""Material panel: pick the elastic material of the sculpting brushes.

Modes: isotropic (Young's modulus E and Poisson ratio ν, or the Lamé parameters λ and μ),
orthotropic (nine engineering constants), transversely isotropic about z (five constants) and
the full symmetric 6×6 Voigt stiffness. The material axes can be rotated by three Euler angles
(extrinsic about x, then y, then z: ``R = Rz(γ) Ry(β) Rx(α)``), applied with
:meth:`gogreen_core.Material.rotated`. A glyph shows the directional Young's modulus.

The panel is a view of two models, every widget bound through :mod:`app.bindings`: the
settings' ``material`` (what the brushes use) and a :class:`~app.panels.material_form.MaterialForm`
(what the inputs hold, always a valid material). An edit the form refuses marks its input red
with the core's message in the panel's words ("Poisson ratio ν must lie in (-1, 1/2)"), and the
settings keep the material in effect. A material that comes from elsewhere (a preset, an undo,
the Homogenize panel) is shown in the mode that fits it; one the panel made itself comes back
with the inputs it was made from.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

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

from app.bindings import (
    Binding,
    bind,
    bind_check,
    bind_choice,
    bind_readout,
    bind_spin,
    bind_view,
)
from app.panels.glyph import YoungModulusGlyph
from app.panels.material_form import (
    FIELD_SPECS,
    ISOTROPIC_EN,
    ISOTROPIC_LAME,
    MODE_TITLES,
    MODES,
    ORTHOTROPIC,
    TRANSVERSE,
    FieldSpec,
    MaterialForm,
    form_values,
)
from app.panels.widgets import (
    CompactNumberDelegate,
    CompactTable,
    EulerAnglesEditor,
    FitStackedWidget,
    NumberField,
    exact_number_text,
    is_marked_invalid,
    set_text_role,
    zero_cell_colors,
)
from gogreen_core.interaction.settings import ChangeEvent, Changes, Settings
from gogreen_core.physics.material import Material
from gogreen_core.physics.material_words import describe_material
from gogreen_core.validation import ParameterError

__all__ = ["MODES", "TINY_VOIGT", "VOIGT_LABELS", "MaterialPanel", "displayed_voigt"]

#: Row/column labels of the Voigt table (order 11, 22, 33, 23, 13, 12; engineering shear).
VOIGT_LABELS = ("11", "22", "33", "23", "13", "12")
_VOIGT_HINT = (
    "Stiffness C in Voigt order 11, 22, 33, 23, 13, 12 (engineering shear). "
    "Editing (i, j) also sets (j, i); must be positive definite."
)
#: Voigt entries smaller than this fraction of the largest are shown as 0 (round-off).
TINY_VOIGT = 1e-9
#: Materials the panel made, with the inputs they were made from (undo shows them again).
_REMEMBERED = 64


def _not(flag: bool) -> bool:
    return not flag


def displayed_voigt(voigt: np.ndarray) -> np.ndarray:
    """The (6, 6) Voigt entries as the table shows them: entries with
    ``|x| < TINY_VOIGT · max|C|`` (round-off of rotations and homogenization, e.g. 1.6e-12
    beside 1) as 0; the stored values keep full precision."""
    voigt = np.asarray(voigt, dtype=np.float64)
    scale = float(np.max(np.abs(voigt))) if voigt.size else 0.0
    return np.where(np.abs(voigt) < TINY_VOIGT * scale, 0.0, voigt)


class MaterialPanel(QWidget):
    """Edit a :class:`gogreen_core.Material`; emits ``material_changed(Material)`` on edits.

    Parameters
    ----------
    material : Material, optional
        Initial material (default isotropic E = 1, ν = 0.3, the sculptor's default), shown in
        the mode that fits it.
    parent : QWidget, optional
    settings : Settings, optional: the model whose ``material`` the panel shows and edits (a
        private one when omitted).

    Attributes
    ----------
    form : MaterialForm, what the inputs hold.
    fields : dict[str, NumberField]
        Every scalar field by key: ``young``, ``poisson``, ``lam``, ``mu``, ``E1`` … ``nu23``,
        ``young_plane``, ``young_axial``, ``poisson_plane``, ``poisson_axial``, ``shear_axial``.
    mode_combo : QComboBox (data: a key of :data:`MODES`)
    lame_radio : QRadioButton checked when the isotropic mode uses λ, μ.
    voigt_table : QTableWidget, 6×6, kept symmetric.
    rotation : EulerAnglesEditor
    frame_combo : QComboBox (data: "world" or "surface"), bound to the settings'
        ``material_frame``: whether the material's axes stay in the world or follow the surface
        where each stroke starts (the rotation then turns them within that frame).
    glyph : YoungModulusGlyph
    error_label : QLabel showing the last refused input (hidden when the input is valid).
    """

    #: Emitted with the new material after each edit made in the panel that changes it.
    material_changed = Signal(object)

    def __init__(
        self,
        material: Material | None = None,
        parent: QWidget | None = None,
        settings: Settings | None = None,
    ):
        super().__init__(parent)
        self.settings = settings if settings is not None else Settings()
        if material is not None:
            self.settings.material = material
        self.form = MaterialForm()
        #: The inputs of each material the panel made (most recent last).
        self._made: OrderedDict[Material, dict[str, Any]] = OrderedDict()
        self.fields: dict[str, NumberField] = {}
        self.bindings: dict[str, Binding] = {}

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 6, 6, 6)
        layout.setSpacing(6)
        self.glyph = YoungModulusGlyph(self.settings.material)
        glyph_box = QGroupBox("Anisotropy: directional Young's modulus E(d)")
        glyph_layout = QVBoxLayout(glyph_box)
        glyph_layout.setContentsMargins(6, 4, 6, 6)
        glyph_layout.addWidget(self.glyph)
        #: What the material does under a brush, in words (bound to the settings' material).
        self.words_label = QLabel()
        self.words_label.setWordWrap(True)
        glyph_layout.addWidget(self.words_label)
        layout.addWidget(glyph_box)

        mode_row = QHBoxLayout()
        mode_row.addWidget(QLabel("Type"))
        self.mode_combo = QComboBox()
        for mode in MODES:
            self.mode_combo.addItem(MODE_TITLES[mode], mode)
        self.mode_combo.setToolTip("How the stiffness is entered")
        mode_row.addWidget(self.mode_combo, 1)
        layout.addLayout(mode_row)

        self.pages = FitStackedWidget()
        self.pages.addWidget(self._isotropic_page())
        self.pages.addWidget(self._grid_page(ORTHOTROPIC, columns=3))
        self.pages.addWidget(self._form_page(TRANSVERSE))
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
        frame_row = QHBoxLayout()
        frame_row.addWidget(QLabel("Axes"))
        self.frame_combo = QComboBox()
        self.frame_combo.addItem("Fixed in the world", "world")
        self.frame_combo.addItem("Follow the surface", "surface")
        self.frame_combo.setToolTip(
            "Follow the surface: each stroke turns the material onto the surface where it "
            "starts (third axis along the normal, first along the stroke), so fibres, grain "
            "and layers act the same anywhere on the model; the rotation below turns them "
            "within that frame"
        )
        frame_row.addWidget(self.frame_combo, 1)
        rotation_layout.addLayout(frame_row)
        self.rotation = EulerAnglesEditor()
        rotation_layout.addWidget(self.rotation)
        layout.addWidget(rotation_box)
        layout.addStretch(1)

        self._bind()
        self._show_material(self.settings.material)

    # -- bindings ----------------------------------------------------------------------------
    def _bind(self) -> None:
        form, error = self.form, self._show_error
        pages, isotropic_pages, young = self.pages, self.isotropic_pages, self.young_radio
        bind_choice(form, "mode", self.mode_combo, label="Type")
        bind_view(form, "mode", pages, lambda mode: pages.setCurrentIndex(MODES.index(mode)))
        bind_check(form, "lame", self.lame_radio)
        bind(form, "lame", young, lambda lame: young.setChecked(not lame), young.toggled, _not)
        bind_view(form, "lame", isotropic_pages, lambda lame: isotropic_pages.setCurrentIndex(lame))
        for key, field in self.fields.items():
            self.bindings[key] = bind_spin(form, key, field, FIELD_SPECS[key].label, on_error=error)
        self.bindings["voigt"] = bind(
            form,
            "voigt",
            self.voigt_table,
            self._fill_voigt_table,
            self.voigt_table.itemChanged,
            self._read_cell,
            label="Stiffness table",
            revert_on_error=lambda exc: "not a number" in str(exc),
            on_error=error,
            echo=True,
        )
        self.bindings["angles"] = bind(
            form,
            "angles",
            self.rotation,
            self.rotation.set_angles,
            self.rotation.changed,
            lambda: self.rotation.angles,
            label="Rotation",
            dragging=self.rotation.is_dragging,
            drag_ended=self.rotation.drag_finished,
            on_error=error,
        )
        bind_choice(self.settings, "material_frame", self.frame_combo, label="Material axes")
        form.events.changed.connect(self._form_changed)
        bind_view(self.settings, "material", self.glyph, self.glyph.set_material)
        bind_readout(self.settings, "material", self.words_label, describe_material)
        emitter, callback = self.settings.events.material, self._model_material
        emitter.connect(callback)
        self.destroyed.connect(lambda *_: emitter.disconnect(callback))

    def _form_changed(self, changes: Changes) -> None:
        """The inputs changed: hand their material to the settings (not when the inputs were
        only loaded from the settings)."""
        self._hide_error()
        if changes.source == "settings":
            return
        material = self.form.material
        self._remember(material)
        if material == self.settings.material:
            return
        self.settings.set("material", material, continued=changes.continued)
        self.material_changed.emit(material)

    def _model_material(self, event: ChangeEvent) -> None:
        if event.value != self.form.material:  # not the inputs' own material coming back
            self._show_material(event.value)

    def _show_material(self, material: Material) -> None:
        """Load the inputs that show ``material``: those it was made from, when the panel
        made it, else those of the mode that fits it (keeping the E, ν / λ, μ choice)."""
        values = self._made.get(material) or form_values(material, lame=self.form.lame)
        self.form.update(values, source="settings")
        self.bindings["voigt"].refresh()  # its zero colours, when the values did not change
        self._hide_error()

    def show_inputs(self, values: dict) -> None:
        """Show the inputs ``values`` (:meth:`MaterialForm.values`, e.g. recovered after a
        crash) when they make the active material: its mode, numbers and rotation angles;
        else the active material as :meth:`_show_material` does (the settings win)."""
        self.form.update(values, source="settings")
        if self.form.material == self.settings.material:
            self._remember(self.form.material)
            self._hide_error()
        else:
            self._show_material(self.settings.material)

    def _remember(self, material: Material) -> None:
        self._made[material] = self.form.values()
        self._made.move_to_end(material)
        while len(self._made) > _REMEMBERED:
            self._made.popitem(last=False)

    # -- pages -------------------------------------------------------------------------------
    def _make_field(self, spec: FieldSpec) -> NumberField:
        field = NumberField(spec.default, spec.minimum, spec.maximum, tooltip=spec.tooltip)
        self.fields[spec.key] = field
        return field

    def _form_page(self, specs: tuple[FieldSpec, ...]) -> QWidget:
        page = QWidget()
        form = QFormLayout(page)
        form.setContentsMargins(0, 0, 0, 0)
        for spec in specs:
            label = QLabel(spec.label)
            label.setToolTip(spec.tooltip)
            form.addRow(label, self._make_field(spec))
        return page

    def _grid_page(self, specs: tuple[FieldSpec, ...], columns: int) -> QWidget:
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
        self._param_group = QButtonGroup(self)
        for radio in (self.young_radio, self.lame_radio):
            self._param_group.addButton(radio)
            toggle.addWidget(radio)
        toggle.addStretch(1)
        layout.addLayout(toggle)
        self.isotropic_pages = FitStackedWidget()
        self.isotropic_pages.addWidget(self._form_page(ISOTROPIC_EN))
        self.isotropic_pages.addWidget(self._form_page(ISOTROPIC_LAME))
        layout.addWidget(self.isotropic_pages)
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
        layout.addWidget(table)
        hint = QLabel("Base stiffness before rotation; (i, j) mirrors (j, i).")
        set_text_role(hint, "muted")
        hint.setWordWrap(True)
        layout.addWidget(hint)
        return page

    # -- public API --------------------------------------------------------------------------
    @property
    def material(self) -> Material:
        """The material in effect (rotation applied): the settings'."""
        return self.settings.material

    @property
    def base_material(self) -> Material:
        """The material of the inputs before the rotation of its axes."""
        return self.form.base_material

    @property
    def mode(self) -> str:
        """Current mode, a key of :data:`MODES`."""
        return self.form.mode

    def set_mode(self, mode: str) -> None:
        """Switch the input mode (``"isotropic"``, ``"orthotropic"``,
        ``"transversely_isotropic"`` or ``"voigt"``); the Voigt mode starts from the current
        base stiffness, the others from their fields."""
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES} (got {mode!r})")
        self.form.mode = mode

    @property
    def error(self) -> str:
        """The message of the last refused input, or "" when the input is valid."""
        return self.error_label.text() if not self.error_label.isHidden() else ""

    def set_material(self, material: Material, emit: bool = False) -> None:
        """Use ``material`` (through the settings), shown in the mode that fits it: an
        isotropic material in the isotropic mode, a transversely isotropic or orthotropic one
        in its mode, any other in the Voigt mode. Emits ``material_changed`` only if ``emit``
        (the caller who loads a material usually applies it itself)."""
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material (got {type(material).__name__})")
        changed = material != self.settings.material
        self.settings.material = material
        self._show_material(material)
        if emit and changed:
            self.material_changed.emit(material)

    def set_field(self, key: str, value: float) -> None:
        """Type ``value`` into field ``key`` (as editing it would), switching to its mode."""
        field = self.fields[key]
        if key in ("young", "poisson", "lam", "mu"):
            self.form.update({"mode": "isotropic", "lame": key in ("lam", "mu")})
        elif key in {s.key for s in ORTHOTROPIC}:
            self.set_mode("orthotropic")
        else:
            self.set_mode("transversely_isotropic")
        field.setValue(value)

    def set_voigt_entry(self, row: int, col: int, value: float | str) -> None:
        """Edit Voigt cell (row, col) as the user would (text), which also sets (col, row)."""
        self.set_mode("voigt")
        self.voigt_table.cell(row, col).setText(str(value))

    def voigt_entries(self) -> np.ndarray:
        """The (6, 6) numbers of the Voigt inputs (base, before rotation)."""
        return np.array(self.form.voigt)

    def invalid_fields(self) -> list[str]:
        """Keys of the fields marked invalid, plus ``"voigt"`` if the table is marked."""
        keys = [k for k, f in self.fields.items() if is_marked_invalid(f)]
        if is_marked_invalid(self.voigt_table):
            keys.append("voigt")
        return keys

    def refresh_colors(self) -> None:
        """Re-colour the Voigt table in the current theme (after a theme switch)."""
        self.bindings["voigt"].refresh()

    # -- the Voigt table ---------------------------------------------------------------------
    def _fill_voigt_table(self, voigt: np.ndarray) -> None:
        shown = displayed_voigt(voigt)
        for i in range(6):
            for j in range(6):
                self._show_voigt_cell(self.voigt_table.cell(i, j), shown[i, j], voigt[i, j])

    def _show_voigt_cell(self, item: QTableWidgetItem, value: float, stored: float) -> None:
        """Text of a Voigt cell: ``value`` exactly (the delegate shows it rounded; the editor
        and the tool tip show it whole, with the stored value when round-off is shown as 0);
        zeros muted, the others in the palette's text colour (a default brush, so that they
        follow the theme)."""
        i, j = item.row(), item.column()
        text = exact_number_text(value)
        tip = f"C{VOIGT_LABELS[i]},{VOIGT_LABELS[j]} = {text}"
        if float(stored) != value:
            tip += f" (stored {exact_number_text(stored)}: round-off, shown as 0)"
        item.setText(text)
        item.setToolTip(f"{tip}\n{_VOIGT_HINT}")
        item.setBackground(QBrush())
        item.setForeground(QBrush(zero_cell_colors()[1]) if value == 0 else QBrush())

    def _read_cell(self, item: QTableWidgetItem) -> np.ndarray:
        """The table's stiffness with cell (i, j) typed; (j, i) shows the same number (its
        change reads the pair again, which then changes nothing)."""
        i, j = item.row(), item.column()
        text = item.text().strip()
        try:
            value = float(text)
        except ValueError:
            value = float("nan")
        if not np.isfinite(value):
            raise ParameterError(
                "voigt", f"C{VOIGT_LABELS[i]},{VOIGT_LABELS[j]}: {text!r} is not a number"
            )
        mirror = self.voigt_table.cell(j, i)
        if mirror.text() != item.text():
            mirror.setText(item.text())
        voigt = np.array(self.form.voigt)
        voigt[i, j] = voigt[j, i] = value
        return voigt

    # -- messages ----------------------------------------------------------------------------
    def _show_error(self, message: str | None) -> None:
        if message is None:
            self._hide_error()
            return
        self.error_label.setText(f"Not applied: {message}")
        self.error_label.show()

    def _hide_error(self) -> None:
        self.error_label.clear()
        self.error_label.hide()
