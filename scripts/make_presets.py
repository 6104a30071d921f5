"""Write the built-in presets to resources/presets/ (run after changing them; files are committed).

    python scripts/make_presets.py

Every preset is built from gogreen_core objects, so a shipped file is always one the program
accepts (tests/core/files/test_presets.py loads each and checks this script would write the same
files).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gogreen_core import (
    Brush,
    GaussianRadial,
    KelvinletRadial,
    Material,
    Preset,
    bimaterial,
    homogenize,
    make_pattern,
    save_preset,
)
from gogreen_core.sculpt.brushes import fold_weights

FOLDER = Path(__file__).resolve().parents[1] / "resources" / "presets"


def _tilt(material: Material, degrees: float) -> Material:
    """Rotate the material axes about x, so its anisotropy is not aligned with the model's."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return material.rotated(rotation)


def builtin() -> dict[str, Preset]:
    """File stem → preset, in menu order."""
    # The wrinkle material: a 1:100 laminate, layers tilted 45° about x. Its ripples are
    # strongest where the layers are tilted to the surface (by symmetry a tangential pull makes
    # none in the normal direction where they lie in the surface or across it). Measured on the
    # default model, default wrinkle weights (the ripple measure of tests/test_wrinkle.py,
    # median of 12 strokes): 1:30 at 20° (the old material) 0.078, 1:30 at 45° 0.093, 1:100
    # at 20° 0.156, 1:100 at 45° 0.192 (grab 0.034-0.056); the grabbed point follows the cursor
    # exactly and no face folded over in 120 strokes of 1.5 ε with either 1:100 tilt.
    laminate = homogenize(make_pattern("layered", 8), bimaterial(contrast=100.0))
    return {
        "01_soft_clay": Preset(
            "Soft clay",
            Material.isotropic(1.0, 0.3),
            GaussianRadial(1.0),
            brush=Brush("grab", radius=0.1),
            description="Isotropic, ν = 0.3, Gaussian falloff: a general-purpose grab.",
        ),
        "02_rubber": Preset(
            "Rubber (volume preserving)",
            Material.isotropic(1.0, 0.49),
            GaussianRadial(1.0),
            brush=Brush("grab", radius=0.08),
            description="Nearly incompressible (ν = 0.49): pulls bulge the sides, volume is kept.",
        ),
        "03_elastic_deform": Preset(
            "Elastic Deform (Kelvinlets)",
            Material.isotropic(1.0, 0.4),
            KelvinletRadial(1.0),
            brush=Brush("grab_triscale", radius=0.08),
            description="Regularized Kelvinlets' tri-scale grab, as Blender's Elastic Deform.",
        ),
        "04_wood_grain": Preset(
            "Wood grain",
            _tilt(
                Material.orthotropic(
                    young=(1.0, 0.6, 12.0), shear=(0.8, 0.9, 0.3), poisson=(0.45, 0.03, 0.03)
                ),
                30.0,
            ),
            GaussianRadial(1.0),
            l_max=10,
            brush=Brush("grab", radius=0.08),
            description="Orthotropic, 12× stiffer along a grain tilted 30° from z.",
        ),
        "05_fibre_composite": Preset(
            "Fibre composite",
            Material.transversely_isotropic(
                young_plane=1.0,
                young_axial=20.0,
                poisson_plane=0.35,
                poisson_axial=0.02,
                shear_axial=0.4,
            ),
            GaussianRadial(1.0),
            l_max=10,
            brush=Brush("twist", radius=0.1),
            description="Transversely isotropic, stiff fibres along z: twists shear along them.",
        ),
        "06_layered_wrinkles": Preset(
            "Layered sheet wrinkles",
            _tilt(laminate, 45.0),
            GaussianRadial(1.0),
            l_max=10,
            brush=Brush("wrinkle", radius=0.06),
            brush_weights={"wrinkle": fold_weights(10, 8)},
            description=(
                "Homogenized 1:100 laminate, layers tilted 45°: the wrinkle brush folds the "
                "surface around the cursor along the layers (fold degree 6, 8 or 10 and the "
                "fold depth in the Falloff panel; rotate the material to turn the folds)."
            ),
        ),
        "07_auxetic_stretch": Preset(
            "Auxetic stretch",
            Material.orthotropic(
                young=(1.0, 1.0, 1.0), shear=(0.4, 0.4, 0.4), poisson=(0.45, -0.45, 0.0)
            ),
            GaussianRadial(1.0),
            brush=Brush("stretch", radius=0.15),
            description=(
                "Orthotropic with Poisson ratios +0.45 (x–y) and −0.45 (x–z): stretched along "
                "x it narrows along y and widens along z (the stretch brush, paper Fig. 11)."
            ),
        ),
    }


def main() -> None:
    FOLDER.mkdir(parents=True, exist_ok=True)
    for stem, preset in builtin().items():
        save_preset(preset, FOLDER / f"{stem}.json")
        print(f"wrote {FOLDER / stem}.json")


if __name__ == "__main__":
    main()
