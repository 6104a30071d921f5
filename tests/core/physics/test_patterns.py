import inspect

import numpy as np
import pytest

from gogreen_core.physics.patterns import (
    PATTERNS,
    checkerboard,
    fibers,
    lattice,
    layered,
    make_pattern,
    random_pattern,
    spheres,
)


def is_binary_cell(ph: np.ndarray, n: int) -> bool:
    return ph.shape == (n, n, n) and ph.dtype == np.int8 and set(np.unique(ph)) <= {0, 1}


def cubic_invariant(ph: np.ndarray) -> bool:
    """Invariant under axis permutations and the reflections x -> -x (about the cell centre)."""
    perms = [(0, 1, 2), (1, 0, 2), (2, 1, 0), (0, 2, 1), (1, 2, 0), (2, 0, 1)]
    same = all(np.array_equal(ph, np.transpose(ph, p)) for p in perms)
    return same and all(np.array_equal(ph, np.flip(ph, ax)) for ax in range(3))


# -- families ---------------------------------------------------------------------------------
@pytest.mark.parametrize(("normal", "axis"), [("x", 0), ("y", 1), ("z", 2), (2, 2)])
def test_layered_varies_only_along_normal(normal, axis):
    ph = layered(12, normal=normal, fraction=1 / 3, periods=2)
    assert is_binary_cell(ph, 12)
    line = np.moveaxis(ph, axis, 0)
    assert np.all(line == line[:, :1, :1])  # constant in the plane of the layers
    assert np.array_equal(line[:, 0, 0], [1, 1, 0, 0, 0, 0] * 2)
    assert np.mean(ph) == pytest.approx(1 / 3)


def test_layered_extremes():
    assert layered(8, fraction=0.0).sum() == 0
    assert layered(8, fraction=1.0).all()


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_fibers_are_straight_along_axis(axis):
    ax = "xyz".index(axis)
    ph = fibers(16, axis=axis, fraction=0.3)
    assert is_binary_cell(ph, 16)
    assert np.all(np.diff(ph, axis=ax) == 0)
    assert abs(np.mean(ph) - 0.3) < 0.03
    section = np.take(ph, 0, axis=ax)
    assert np.array_equal(section, section.T) and np.array_equal(section, np.flip(section, 0))
    assert section[8, 8] == 1 and section[0, 0] == 0  # centred rod


def test_fibers_square_and_periods():
    ph = fibers(16, fraction=0.25, periods=2, shape="square")
    assert np.mean(ph) == 0.25
    assert np.array_equal(ph, np.roll(ph, 8, axis=0)) and np.array_equal(ph, np.roll(ph, 8, 1))
    with pytest.raises(ValueError, match="pi/4"):
        fibers(16, fraction=0.9)
    with pytest.raises(ValueError, match="shape"):
        fibers(16, shape="hexagonal")


@pytest.mark.parametrize(("n", "periods"), [(2, 1), (8, 1), (12, 3)])
def test_checkerboard(n, periods):
    ph = checkerboard(n, periods)
    assert is_binary_cell(ph, n)
    assert np.mean(ph) == 0.5
    half = n // (2 * periods)
    for ax in range(3):  # shifting by one block swaps the phases
        assert np.array_equal(np.roll(ph, half, axis=ax), 1 - ph)
    for perm in [(1, 0, 2), (2, 1, 0), (1, 2, 0)]:
        assert np.array_equal(ph, np.transpose(ph, perm))
    if periods == 1:  # a mirror swaps the two blocks of a period
        assert np.array_equal(np.flip(ph, 0), 1 - ph)


@pytest.mark.parametrize("arrangement", ["sc", "bcc", "fcc"])
def test_spheres(arrangement):
    ph = spheres(16, fraction=0.2, arrangement=arrangement)
    assert is_binary_cell(ph, 16)
    assert abs(np.mean(ph) - 0.2) < 0.03
    assert cubic_invariant(ph)


def test_spheres_limits():
    with pytest.raises(ValueError, match="touch"):
        spheres(16, fraction=0.6)  # above pi/6 for sc
    assert spheres(16, fraction=0.6, arrangement="bcc").any()
    with pytest.raises(ValueError, match="arrangement"):
        spheres(16, arrangement="hcp")


def test_lattice():
    ph = lattice(16, fraction=0.3)
    assert is_binary_cell(ph, 16)
    assert abs(np.mean(ph) - 0.3) < 0.05
    assert cubic_invariant(ph)
    cross = lattice(16, fraction=0.3, axes="xy")
    assert not cross[:, :, 0].any() and cross[:, :, 8].any()  # bars in the plane z = 1/2
    assert np.array_equal(cross, np.transpose(cross, (1, 0, 2)))
    assert not np.array_equal(cross, np.transpose(cross, (2, 1, 0)))
    assert lattice(16, fraction=1.0).all() and not lattice(16, fraction=0.0).any()
    with pytest.raises(ValueError, match="axes"):
        lattice(16, axes="xx")


def test_lattice_bar_width_hits_fraction_on_fine_grid():
    for axes, frac in (("xyz", 0.2), ("xz", 0.4), ("y", 0.25)):
        assert abs(np.mean(lattice(64, fraction=frac, axes=axes)) - frac) < 0.02


def test_random_pattern():
    a = random_pattern(10, 0.37, seed=5)
    assert is_binary_cell(a, 10)
    assert a.sum() == round(0.37 * 1000)
    assert np.array_equal(a, random_pattern(10, 0.37, seed=5))
    assert not np.array_equal(a, random_pattern(10, 0.37, seed=6))
    blobs = random_pattern(16, 0.5, seed=1, correlation=0.1)
    voxels = random_pattern(16, 0.5, seed=1)
    assert blobs.sum() == voxels.sum()

    def interfaces(ph):
        return sum(int((ph != np.roll(ph, 1, axis=ax)).sum()) for ax in range(3))

    assert interfaces(blobs) < 0.5 * interfaces(voxels)  # smoothing gives blobs


# -- registry ---------------------------------------------------------------------------------
def test_registry_has_the_paper_families():
    assert {"layered", "fibers", "checkerboard", "spheres", "lattice", "random"} <= set(PATTERNS)


@pytest.mark.parametrize("name", list(PATTERNS))
def test_registry_entries_match_their_functions(name):
    spec = PATTERNS[name]
    sig = inspect.signature(spec.function)
    assert "n" in sig.parameters
    for p in spec.parameters:
        assert p.name in sig.parameters
        assert sig.parameters[p.name].default == p.default
        assert p.kind in ("int", "float", "choice")
        if p.kind == "choice":
            assert p.default in p.choices
        assert p.description
    ph = make_pattern(name, 8)
    assert is_binary_cell(ph, 8)
    assert np.array_equal(ph, spec.function(n=8))


def test_make_pattern_errors():
    with pytest.raises(ValueError, match="unknown pattern"):
        make_pattern("stripes")
    with pytest.raises(ValueError, match="unknown parameter"):
        make_pattern("layered", 8, radius=3)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: layered(1), "n must be ≥ 2"),
        (lambda: layered(8.5), "integer"),
        (lambda: layered(8, normal="w"), "normal"),
        (lambda: layered(8, fraction=-0.1), "fraction"),
        (lambda: layered(8, fraction=float("nan")), "fraction"),
        (lambda: layered(8, periods=0), "periods"),
        (lambda: layered(8, periods=9), "too many"),
        (lambda: checkerboard(8, periods=5), "too many"),
        (lambda: random_pattern(8, correlation=-1.0), "correlation"),
    ],
)
def test_invalid_parameters_raise(call, message):
    with pytest.raises(ValueError, match=message):
        call()
