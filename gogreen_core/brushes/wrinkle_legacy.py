"""The wrinkle brush of sessions before version 3 (``wrinkle_legacy``): a grab whose field uses
reweighted SH degrees (paper Fig. 10) with the Gaussian's own radial terms.

Kept so that those sessions replay bit for bit (they call it ``wrinkle``; the session reader
renames it); the folding wrinkle brush of :mod:`gogreen_core.brushes.wrinkle` replaced it
because inside the brush these radial terms leave the high degrees 20-250 times smaller than
degree 0, so it made no folds. The force is fixed by the full kernel (the grabbed point follows
the cursor, as with ``grab``), the field by the per-degree weights ω_l of the settings
(``degree_weights``), which bring out the angular ripples of high degrees
(:func:`default_wrinkle_weights`). Only an anisotropic material has such degrees (an isotropic
one has l ≤ 2, so wrinkle = grab); the ripples follow its layers or fibres and are strongest
where they are tilted to the surface (a laminate whose layers lie in or across the surface makes
none in the surface's normal direction, by symmetry).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.brushes.grab import GrabBrush
from gogreen_core.limits import check_l_max
from gogreen_core.radial import GaussianRadial
from gogreen_core.validation import check_integer

if TYPE_CHECKING:
    from gogreen_core.engine_settings import EngineSettings

__all__ = [
    "WRINKLE_LEVEL",
    "WRINKLE_RING",
    "WRINKLE_TOP_DEGREE",
    "LegacyWrinkleBrush",
    "default_wrinkle_weights",
    "legacy_wrinkle_weights",
]


def legacy_wrinkle_weights(l_max: int) -> np.ndarray:
    """The wrinkle weights max(1, l/2) (l_max + 1,) that ``degree_weights = None`` means in
    the engine: sessions and presets recorded ``null`` for them before
    :func:`~gogreen_core.brushes.default_wrinkle_weights` changed, so None keeps this meaning
    and they replay exactly; new code records the weights it uses explicitly."""
    l_max = check_l_max(l_max)
    return np.maximum(1.0, np.arange(l_max + 1) / 2.0)


#: Radius (in ε) at which :func:`default_wrinkle_weights` equalizes the degrees' radial terms.
WRINKLE_RING = 2.5
#: Highest degree :func:`default_wrinkle_weights` boosts.
WRINKLE_TOP_DEGREE = 8
#: Level the boosted degrees' Gaussian radial terms are brought to at :data:`WRINKLE_RING`, as
#: a fraction of R_0 there (see :func:`default_wrinkle_weights`).
WRINKLE_LEVEL = 0.6


def default_wrinkle_weights(l_max: int) -> np.ndarray:
    """Per-degree weights of the legacy wrinkle brush (l_max + 1,): what the app, the presets and
    "Use a wrinkle material" started with before the folding wrinkle brush.

    Degree l's field is Y_l(x̂) R_l(r) P_l: its angular ripples (up to l around a ring) are
    there whenever the material is anisotropic, but R_l(r) grows like r^l, so within the brush
    (r ≲ 2.5ε; the cutoff fades the field from 2ε to 4ε) the Gaussian R_4, R_6, R_8 are 6, 18
    and 59 times smaller than R_0 at 2.5ε (10, 40, 195 at 2ε), and the old weights
    max(1, l/2) left them invisible (a stroke differed from grab by ~5 % of its largest
    displacement). Here each degree 2 < l ≤ :data:`WRINKLE_TOP_DEGREE` is weighted so its
    Gaussian radial term reaches :data:`WRINKLE_LEVEL` = 0.6 of R_0 at ρ = :data:`WRINKLE_RING`
    = 2.5: w_l = 0.6 R_0(2.5 ε) / R_l(2.5 ε), i.e. 3.79, 10.67, 35.54 for l = 4, 6, 8.
    Measured on the default model with the "Layered sheet wrinkles" material
    (``python tests/test_wrinkle.py``, strokes of 10 events, 1 ε in all): normal ripples
    around the brush 0.19 of the stroke's largest displacement (median; grab 0.056, the old
    weights 0.045 with the old 1:30 material), the grabbed point following the cursor exactly;
    and no face folded over in 120 strokes of 1.5 ε. With the layers tilted 20°, level 0.6
    gave ripples 0.16 and no fold, 0.75 gave 0.18 but folded faces in 3 strokes of those 120,
    1.0 gave 0.22 and 2 (the ripples are compressions: the events of a stroke repeat them
    until they fold), 0.5 gave 0.13. Degrees above 8 keep weight 1: their radial terms peak
    beyond the brush (R_10(2.5ε) = 0.004 R_0(2.5ε)), so boosting them only raises a wall at
    the rim, and the safe falloff bound then scales the whole stroke down (l_max 12, all
    boosted: the surface moved 0.3 × the cursor motion, with no stronger ripples). Degrees
    ≤ 2 keep 1: they make no ripples. Odd entries are unused by G (∇G's degree l uses weight
    l − 1). Rounded to 2 decimals (the Falloff panel shows 2: editing one weight there leaves
    the others).
    """
    l_max = check_integer("l_max", l_max, low=0)
    weights = np.ones(l_max + 1)
    degrees = np.arange(3, min(l_max, WRINKLE_TOP_DEGREE) + 1)
    if len(degrees):
        gaussian, ring = GaussianRadial(1.0), np.array([WRINKLE_RING])
        r0 = gaussian.radial(0, ring)[0]
        weights[degrees] = [WRINKLE_LEVEL * r0 / gaussian.radial(int(l), ring)[0] for l in degrees]
    return np.round(weights, 2)


class LegacyWrinkleBrush(GrabBrush):
    """A grab whose field has the settings' wrinkle weights (:attr:`EngineSettings.
    wrinkle_weights`: ``degree_weights``, or the legacy ones when None), its force from the
    full kernel; its influence is 4 ε unless the stroke says otherwise (sessions before version
    3 always do)."""

    force_from_full = True
    weighted = False  # its weights are the settings' degree_weights, not brush_weights

    def degree_weights(self, settings: EngineSettings) -> np.ndarray | None:
        return settings.wrinkle_weights
