"""The main window's status bar: messages, counts, timings and progress bars."""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING

from PySide6.QtWidgets import QLabel, QProgressBar, QPushButton, QStatusBar

from gogreen_core.files.presets import builtin_presets
from gogreen_core.physics.material import Material
from gogreen_core.physics.material_words import material_name

if TYPE_CHECKING:
    from app.main_window import MainWindow

__all__ = ["StatusArea", "active_material_name", "compile_progress_text"]


@cache
def _preset_materials() -> tuple[tuple[str, Material], ...]:
    """The built-in presets' names and materials (read once)."""
    return tuple((preset.name, preset.material) for preset in builtin_presets())


def active_material_name(window: MainWindow) -> str:
    """The active material's name: a built-in preset's name when it is one's, its kind and
    anisotropy (:func:`material_name`), and the Material panel's rotation of its axes."""
    material = window.model.material
    name = material_name(material)
    preset = next((n for n, m in _preset_materials() if m == material), None)
    if preset is not None:
        name = f"{preset} ({name})"
    angles = window.material_panel.form.angles
    if any(angles):
        name += " · axes turned " + ", ".join(f"{a:g}°" for a in angles)
    return name


def _time_left(seconds_left: float | None) -> str:
    """The time left, "about 25 s left" (None: not measured yet)."""
    if seconds_left is None:
        return "estimating the time left"
    if seconds_left < 60:
        return f"about {max(5, 5 * round(seconds_left / 5))} s left"
    return f"about {round(seconds_left / 60)} min left"


def compile_progress_text(
    done: int, total: int, seconds_left: float | None, compiling: str = ""
) -> str:
    """What the status bar says while the brush kernels compile: what is compiling now, the
    units compiled of how many, about how long is left (None: not known) and that strokes run
    on the NumPy path meanwhile."""
    now = f" (now the {compiling})" if compiling else ""
    return (
        f"Compiling brush kernels{now}: {done} of {total} units, {_time_left(seconds_left)} — "
        "strokes run on the NumPy path meanwhile"
    )


class StatusArea:
    """The widgets of ``bar``: the message line (``message_label``), the vertex count, the
    last brush step and render times, two progress bars (kernel compilation, the background
    build of a big mesh's surface index) and the wrinkle brush's fix button."""

    def __init__(self, bar: QStatusBar) -> None:
        self.bar = bar
        self.vertex_label = QLabel()
        self.step_label = QLabel("brush step: –")
        self.frame_label = QLabel("render: –")
        self.message_label = QLabel()
        self._busy = ""  # the message of a slow brush step (show_busy)
        # the active material, named at all times (it stays when another model is opened)
        self.material_label = QLabel()
        self.material_label.setToolTip(
            "The active material: every brush uses it. It stays when another model is opened "
            "or a new one made; the Material panel or a preset changes it"
        )
        # Busy indicator while kernels compile (first start, a new l_max): never a silent wait.
        self.compile_progress = self.add_progress(
            0,
            "",
            "Compiling the brush kernels (once per machine and l_max); strokes run on the "
            "slower NumPy path meanwhile",
        )
        self.compile_progress.setMaximumWidth(240)  # "kernels 2/5, about 25 s left"
        # Progress of the background build of a big mesh's surface index (picking, shading)
        self.surface_progress = self.add_progress(
            100,
            "preparing %p%",
            "Preparing the opened mesh for picking and smooth shading; strokes start after it",
        )
        bar.addPermanentWidget(self.material_label)
        for label in (self.vertex_label, self.step_label, self.frame_label):
            label.setMinimumWidth(150)
            bar.addPermanentWidget(label)
        bar.addWidget(self.message_label, 1)
        # one click to a material the wrinkle brush needs (shown only when it lacks one)
        self.wrinkle_fix_button = QPushButton("Use a wrinkle material")
        self.wrinkle_fix_button.setToolTip(
            "Apply the “Layered sheet wrinkles” material and wrinkle weights (one undo step)"
        )
        self.wrinkle_fix_button.hide()
        bar.addWidget(self.wrinkle_fix_button)
        # a temporary message (the first-run hint) is drawn where the label is: not both
        bar.messageChanged.connect(lambda text: self.message_label.setHidden(bool(text)))

    def add_progress(self, maximum: int, text: str, tip: str) -> QProgressBar:
        """A hidden progress bar at the right of the status bar (``maximum`` 0: busy, no
        fraction): ``text`` its format (``"%p%"``), ``tip`` its tool tip."""
        progress = QProgressBar()
        progress.setRange(0, maximum)
        progress.setMaximumWidth(160)
        progress.setFormat(text)
        progress.setToolTip(tip)
        progress.hide()
        self.bar.addPermanentWidget(progress)
        return progress

    def show_compile_progress(
        self, done: int, total: int, seconds_left: float | None, compiling: str = ""
    ) -> str:
        """The compilation's bar at ``done`` of ``total`` units; returns the label to say
        (:func:`compile_progress_text`)."""
        text = compile_progress_text(done, total, seconds_left, compiling)
        self.compile_progress.setRange(0, total)
        self.compile_progress.setValue(done)
        # the bar says it in short too: a temporary hint (the first-run one) may cover the line
        left = "" if seconds_left is None else f", {_time_left(seconds_left)}"
        self.compile_progress.setFormat(f"kernels {done}/{total}{left}")
        self.compile_progress.setToolTip(text)
        return text

    def show_material(self, name: str) -> None:
        """Name the active material (``name``: what it is, e.g. a preset's name and its kind)."""
        self.material_label.setText(f"Material: {name}")

    def show_counts(self, vertices: int | None, step_ms: float) -> None:
        """The vertex count (None: keep it) and the last brush step's time."""
        if vertices is not None:
            self.vertex_label.setText(f"{vertices:,} vertices")
        self.step_label.setText(f"brush step: {step_ms:.1f} ms")

    def show_busy(self, text: str) -> None:
        """Say what a slow brush step does (``text``), or, "", take that back if still said."""
        if text:
            self.message_label.setText(text)
        elif self.message_label.text() == self._busy:
            self.message_label.clear()
        self._busy = text

    def show_frame_time(self, ms: float) -> None:
        self.frame_label.setText(f"render: {ms:.0f} ms")

    def show_surface_progress(self, done: float) -> None:
        self.surface_progress.setValue(round(100 * done))
