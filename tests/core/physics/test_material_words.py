"""Materials described in an artist's words (paper-controls issue, item 7): the kind (fibres,
layers, isotropic), its axis, the stiffness ratio and any sideways widening, read off the
material itself, checked on materials whose answer is known by construction."""

import numpy as np
import pytest

from gogreen_core import Material, bimaterial, builtin_presets, homogenize, make_pattern
from gogreen_core.physics.material_words import describe_material, direction_words, material_traits


def _tilted(material: Material, degrees: float) -> Material:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return material.rotated(np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]]))


def test_isotropic_materials_say_how_the_sides_move():
    assert describe_material(Material.isotropic(1.0, 0.3)) == (
        "The same in every direction: a pull thins the sides a little (ν = 0.30)."
    )
    assert "keeps the volume" in describe_material(Material.isotropic(2.0, 0.49))
    assert "widens the sides" in describe_material(Material.isotropic(1.0, -0.5))


def test_a_stiff_axis_reads_as_fibres_along_it():
    fibres = Material.transversely_isotropic(1.0, 20.0, 0.3, 0.02, 0.4)  # stiff along z
    traits = material_traits(fibres)
    assert traits.kind == "fibres"
    assert abs(traits.axis[2]) > 0.999
    assert traits.ratio == pytest.approx(20.0, rel=0.05)
    assert describe_material(fibres).startswith("Fibres along Z, 20")
    tilted = describe_material(_tilted(fibres, 30.0))
    assert tilted.startswith("Fibres along Z tilted 30° toward −Y")


def test_a_soft_axis_reads_as_layers_stacked_along_it():
    laminate = homogenize(make_pattern("layered", 8), bimaterial(contrast=100.0))
    traits = material_traits(laminate)
    assert traits.kind == "layers"
    assert abs(traits.axis[2]) > 0.999  # the pattern's layers are stacked along z
    assert "ripple along the layers" in describe_material(laminate)
    preset = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    assert "Layers stacked along Z tilted 45° toward −Y" in describe_material(preset.material)


def test_negative_poisson_ratios_are_named():
    auxetic = Material.orthotropic(
        young=(1.0, 1.0, 1.0), shear=(0.4, 0.4, 0.4), poisson=(0.45, -0.45, 0.0)
    )
    assert "A stretch along X widens it along Z (ν = -0.45)." in describe_material(auxetic)
    assert "widens" not in describe_material(Material.cubic(3.0, 1.5, 0.4))


@pytest.mark.parametrize(
    ("direction", "words"),
    [
        ((0, 0, 1), "Z"),
        ((0, 0, -1), "Z"),
        ((0.1, 0, 1), "Z"),
        ((0, -1, 1), "Y tilted 45° toward −Z"),
        ((1, 1, 1), "X tilted 55° toward Y and Z"),
    ],
)
def test_directions_in_words(direction, words):
    assert direction_words(np.array(direction, dtype=float)) == words


def test_one_anisotropy_figure_whatever_the_rotation(qtbot):
    """The glyph's legend and the words give the same E_max / E_min, from one function, for
    a fibre material turned between any fixed sample directions (it read "max/min 13.7" and
    "17.8× stiffer" for one material)."""
    from scipy.spatial.transform import Rotation

    from app.panels.glyph import YoungModulusGlyph
    from gogreen_core.physics.material_words import young_extremes

    fibres = next(p.material for p in builtin_presets() if p.name == "Fibre composite")
    turn = Rotation.from_euler("xyz", [30.0, 17.0, 41.0], degrees=True).as_matrix()
    ratios = []
    for material in (fibres, fibres.rotated(turn)):
        e_min, e_max, _, _ = young_extremes(material)
        glyph = YoungModulusGlyph(material)
        qtbot.addWidget(glyph)
        assert glyph.young_range == (e_min, e_max)
        assert material_traits(material).ratio == pytest.approx(e_max / e_min, rel=1e-12)
        assert f"{e_max / e_min:.3g}× stiffer" in describe_material(material)
        ratios.append(e_max / e_min)
    assert ratios[1] == pytest.approx(ratios[0], rel=1e-4)  # the same material, turned
