"""What the wrinkle brush needs, said where the artist looks: its tool tip, the status bar and
a one-click fix ("Use a wrinkle material")."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from PySide6.QtCore import QObject
from PySide6.QtGui import QAction
from PySide6.QtWidgets import QPushButton

from gogreen_core.files.presets import Preset, builtin_presets
from gogreen_core.interaction.settings import Settings
from gogreen_core.physics.material import Material

__all__ = [
    "WRINKLE_MIN_ANISOTROPY",
    "WRINKLE_NEEDS",
    "WRINKLE_TIP",
    "WrinkleHint",
    "material_anisotropy",
    "wrinkle_preset",
]

#: Below this :func:`material_anisotropy` the wrinkle brush moves the surface like grab (its
#: reweighted degrees l > 2 carry next to nothing): the cubic c11=1, c12=.5, c44=.4 is 0.13,
#: the built-in layered / wood / fibre presets 0.65 to 0.83.
WRINKLE_MIN_ANISOTROPY = 0.25
WRINKLE_NEEDS = (
    "needs a layered or fibred (anisotropic) material: on this uniform one it pulls without folds"
)
#: Tool tip of the wrinkle brush: what it does and what it needs, in an artist's words.
WRINKLE_TIP = (
    "Wrinkle: pulls the surface and folds it around the pull, along the material's layers "
    "or fibres; needs a layered material such as the “Layered sheet wrinkles” preset (fold "
    "degree and depth: Falloff panel; rotate the material to turn the folds)"
)


def material_anisotropy(material: Material) -> float:
    """‖C − C_iso‖ / ‖C‖ (Frobenius, on the 3×3×3×3 tensor): 0 for an isotropic material,
    where C_iso, the closest isotropic tensor, has the same C_iijj and C_ijij."""
    c = material.tensor
    eye = np.eye(3)
    trace, shear = np.einsum("iijj", c), np.einsum("ijij", c)  # 9λ + 6μ, 3λ + 12μ
    mu = (3.0 * shear - trace) / 30.0
    lam = (trace - 6.0 * mu) / 9.0
    iso = lam * np.einsum("ij,kl", eye, eye) + mu * (
        np.einsum("ik,jl", eye, eye) + np.einsum("il,jk", eye, eye)
    )
    norm = np.linalg.norm(c)
    return float(np.linalg.norm(c - iso) / norm) if norm > 0 else 0.0


def wrinkle_preset() -> Preset:
    """The built-in preset made for the wrinkle brush ("Layered sheet wrinkles")."""
    return next(p for p in builtin_presets() if p.brush.kind == "wrinkle")


class WrinkleHint(QObject):
    """Watches the brush kind and the material of ``model``: while the wrinkle brush is picked
    with a (nearly) isotropic material, its tool tip says what it needs, the status bar says it
    once (``flash``) and ``button`` (the fix) is shown."""

    def __init__(
        self,
        model: Settings,
        action: QAction,
        button: QPushButton,
        flash: Callable[[str], None],
    ) -> None:
        super().__init__(button)
        self.model, self.action, self.button, self.flash = model, action, button, flash
        shortcut = action.toolTip().rpartition("  [")
        self._tip = WRINKLE_TIP + (shortcut[1] + shortcut[2] if shortcut[1] else "")
        button.clicked.connect(self.use_wrinkle_material)
        model.brush.events.kind.connect(lambda _e: self.check())
        model.events.material.connect(lambda _e: self.check())
        self.check()

    @property
    def lacking(self) -> bool:
        """The wrinkle brush is picked and the material is (nearly) isotropic."""
        return (
            self.model.brush.kind == "wrinkle"
            and material_anisotropy(self.model.material) < WRINKLE_MIN_ANISOTROPY
        )

    def check(self) -> None:
        """Say what the wrinkle brush needs (status bar, its tool tip) and offer the fix."""
        lacking = self.lacking
        note = f"\n{WRINKLE_NEEDS[0].upper()}{WRINKLE_NEEDS[1:]}."
        self.action.setToolTip(self._tip + (note if lacking else ""))
        if lacking and self.button.isHidden():
            self.flash(f"Wrinkle {WRINKLE_NEEDS}.")
        self.button.setVisible(lacking)

    def use_wrinkle_material(self) -> None:
        """Apply the wrinkle preset's material, and its l_max and fold weights when this model's
        l_max is lower (folds need the degrees): one undo step."""
        preset = wrinkle_preset()
        changed = self.model.update({"material": preset.material})
        if self.model.l_max < preset.l_max:
            # continued: the falloff group joins the material's undo step
            weights = preset.engine_settings().weights_for("wrinkle")
            self.model.update({"l_max": preset.l_max}, continued=bool(changed))
            self.model.set_brush_weights("wrinkle", weights.tolist(), continued=True)
        self.flash(f"Wrinkle material: {preset.name} (Ctrl+Z undoes it)")
