"""Periodic two-phase voxel patterns for :func:`gogreen_core.homogenize` (the families of Go
Green's Fig. 12): each returns one periodic cell as an (n, n, n) ``int8`` array of 0/1, axis
order x, y, z; 0 is phase a (the matrix), 1 phase b (inclusions, fibres, bars, odd layers).

The cell is the unit cube; voxel (i, j, k) is phase b when its centre ((i, j, k) + 1/2) / n lies
inside the shape. ``periods`` repeats the motif along each axis; axes are ``"x"``, ``"y"``,
``"z"`` or 0, 1, 2. :data:`PATTERNS` lists each family with its typed parameters (for a GUI).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from gogreen_core.validation import check_choice, check_integer, check_number

__all__ = [
    "PATTERNS",
    "PatternParameter",
    "PatternSpec",
    "checkerboard",
    "fibers",
    "lattice",
    "layered",
    "make_pattern",
    "random_pattern",
    "spheres",
]

_AXES = {"x": 0, "y": 1, "z": 2, 0: 0, 1: 1, 2: 2}

# Close packing limits of the volume fraction of each shape (touching neighbours).
_MAX_FIBER_FRACTION = np.pi / 4.0
_SPHERE_LATTICES: dict[str, tuple[np.ndarray, float]] = {
    # centres in one motif (unit cube) and the touching-sphere packing fraction
    "sc": (np.array([[0.5, 0.5, 0.5]]), np.pi / 6.0),
    "bcc": (np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]]), np.pi * np.sqrt(3.0) / 8.0),
    "fcc": (
        np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]]),
        np.pi / (3.0 * np.sqrt(2.0)),
    ),
}


def _check_fraction(fraction: float, upper: float = 1.0, what: str = "") -> float:
    f = float(fraction)
    if not np.isfinite(f) or not 0.0 <= f <= upper:
        extra = f" ({what})" if what else ""
        raise ValueError(f"fraction must lie in [0, {upper:.6g}]{extra} (got {fraction})")
    return f


def _check_grid(n: int, periods: int, per_period: int = 1) -> tuple[int, int]:
    n = check_integer("n", n, low=2)
    periods = check_integer("periods", periods, low=1)
    if periods * per_period > n:
        raise ValueError(
            f"periods = {periods} is too many for n = {n}: need periods * {per_period} <= n"
        )
    return n, periods


def _check_axis(axis: str | int, name: str = "axis") -> int:
    key = axis.lower() if isinstance(axis, str) else axis
    if key not in _AXES:
        raise ValueError(f"{name} must be 'x', 'y', 'z' or 0, 1, 2 (got {axis!r})")
    return _AXES[key]


def _motif_coords(n: int, periods: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Voxel-centre coordinates in motif units, each in [0, 1): three (n, n, n) arrays."""
    t = ((np.arange(n) + 0.5) / n * periods) % 1.0
    return np.meshgrid(t, t, t, indexing="ij")


def _periodic_distance(t: np.ndarray, centre: float) -> np.ndarray:
    d = np.abs(t - centre) % 1.0
    return np.minimum(d, 1.0 - d)


def layered(
    n: int = 16, normal: str | int = "z", fraction: float = 0.5, periods: int = 1
) -> np.ndarray:
    """Laminate: layers of phase b (thickness ``fraction`` of each period) stacked along
    ``normal``: transversely isotropic about it (exact Backus tensor)."""
    n, periods = _check_grid(n, periods)
    ax = _check_axis(normal, "normal")
    f = _check_fraction(fraction)
    return (_motif_coords(n, periods)[ax] < f).astype(np.int8)


def fibers(
    n: int = 16,
    axis: str | int = "z",
    fraction: float = 0.3,
    periods: int = 1,
    shape: str = "round",
) -> np.ndarray:
    """Fibre-reinforced: straight rods of phase b along ``axis`` on a square array, one rod per
    motif centre. ``shape`` "round" (circular section, fraction <= pi/4) or "square" (fraction
    <= 1): tetragonal about ``axis``."""
    n, periods = _check_grid(n, periods)
    ax = _check_axis(axis)
    if check_choice("shape", shape, ("round", "square")) == "square":
        return lattice(n, fraction, periods, "xyz"[ax])
    f = _check_fraction(fraction, _MAX_FIBER_FRACTION, "round fibres touch at pi/4")
    coords = _motif_coords(n, periods)
    u, v = (coords[i] for i in range(3) if i != ax)
    inside = _periodic_distance(u, 0.5) ** 2 + _periodic_distance(v, 0.5) ** 2 < f / np.pi
    return cast(np.ndarray, inside.astype(np.int8))


def checkerboard(n: int = 16, periods: int = 1) -> np.ndarray:
    """3D checkerboard: 2 x 2 x 2 blocks per motif, phase b where the block indices sum to an
    odd number. Fraction 1/2, cubic symmetry; needs 2 * periods <= n."""
    n, periods = _check_grid(n, periods, per_period=2)
    x, y, z = _motif_coords(n, periods)
    blocks = np.floor(2 * x) + np.floor(2 * y) + np.floor(2 * z)
    return cast(np.ndarray, (blocks.astype(np.int64) % 2).astype(np.int8))


def spheres(
    n: int = 16, fraction: float = 0.2, periods: int = 1, arrangement: str = "sc"
) -> np.ndarray:
    """Spotted: spherical inclusions of phase b on a simple cubic ("sc"), body-centred ("bcc")
    or face-centred ("fcc") lattice, radius from ``fraction`` (at most the touching-sphere
    packing: pi/6 for sc, 0.680 for bcc, 0.740 for fcc). Cubic symmetry."""
    n, periods = _check_grid(n, periods)
    centres, f_max = _SPHERE_LATTICES[
        check_choice("arrangement", arrangement, ("sc", "bcc", "fcc"))
    ]
    f = _check_fraction(fraction, f_max, f"spheres of a {arrangement} lattice touch at {f_max:.4g}")
    x, y, z = _motif_coords(n, periods)
    radius2 = (3.0 * f / (4.0 * np.pi * len(centres))) ** (2.0 / 3.0)
    inside = np.zeros((n, n, n), dtype=bool)
    for cx, cy, cz in centres:
        d2 = (
            _periodic_distance(x, cx) ** 2
            + _periodic_distance(y, cy) ** 2
            + _periodic_distance(z, cz) ** 2
        )
        inside |= d2 < radius2
    return inside.astype(np.int8)


def _bar_width(fraction: float, count: int) -> float:
    """Side w of ``count`` orthogonal square bars covering ``fraction``: w², 2w² - w³, 3w² - 2w³."""
    if count == 1:
        return float(np.sqrt(fraction))
    coef = {2: [-1.0, 2.0, 0.0, -fraction], 3: [-2.0, 3.0, 0.0, -fraction]}[count]
    roots = np.roots(coef)
    real = roots[np.abs(roots.imag) < 1e-9].real
    return float(np.min(real[(real >= -1e-12) & (real <= 1.0 + 1e-12)]).clip(0.0, 1.0))


def lattice(n: int = 16, fraction: float = 0.3, periods: int = 1, axes: str = "xyz") -> np.ndarray:
    """Cross / lattice: square bars of phase b through the motif centre along each axis in
    ``axes`` ("xyz": a 3D cubic lattice/frame, cubic symmetry; "xy", "xz", "yz": a 2D cross of
    bars; one letter: square fibres). Bar width from ``fraction``."""
    n, periods = _check_grid(n, periods)
    f = _check_fraction(fraction)
    letters = sorted({_check_axis(a, "axes") for a in axes}) if isinstance(axes, str) else []
    if not letters or len(letters) != len(axes):
        raise ValueError(f"axes must be distinct letters among 'x', 'y', 'z' (got {axes!r})")
    half = 0.5 * _bar_width(f, len(letters))
    coords = _motif_coords(n, periods)
    near = [_periodic_distance(c, 0.5) < half for c in coords]
    inside = np.zeros((n, n, n), dtype=bool)
    for ax in letters:
        others = [near[i] for i in range(3) if i != ax]
        inside |= others[0] & others[1]
    return inside.astype(np.int8)


def random_pattern(
    n: int = 16, fraction: float = 0.5, seed: int = 0, correlation: float = 0.0
) -> np.ndarray:
    """Random two-phase microstructure with exactly round(fraction * n^3) voxels of phase b.

    ``correlation`` = 0 draws voxels independently; > 0 thresholds periodic Gaussian-smoothed
    noise (standard deviation ``correlation`` in cell units, e.g. 0.05) into blobs.
    Statistically isotropic, deterministic for a given ``seed``."""
    n = check_integer("n", n, low=2)
    f = _check_fraction(fraction)
    corr = check_number("correlation", correlation, low=0.0)
    rng = np.random.default_rng(seed)
    noise = rng.random((n, n, n))
    if corr > 0:
        k = np.fft.fftfreq(n)
        kr = np.fft.rfftfreq(n)
        k2 = k[:, None, None] ** 2 + k[None, :, None] ** 2 + kr[None, None, :] ** 2
        # Gaussian kernel of std `corr` (cell units) = n * corr voxels, applied periodically.
        filt = np.exp(-2.0 * (np.pi * n * corr) ** 2 * k2)
        noise = np.fft.irfftn(np.fft.rfftn(noise) * filt, s=(n, n, n), axes=(0, 1, 2))
    count = round(f * n**3)
    out = np.zeros(n**3, dtype=np.int8)
    if count > 0:
        order = np.argsort(noise, axis=None, kind="stable")
        out[order[:count]] = 1
    return out.reshape(n, n, n)


@dataclass(frozen=True)
class PatternParameter:
    """One parameter of a pattern family, for GUI widgets: ``kind`` "int", "float" or
    "choice"; ``low``/``high`` bound numbers, ``choices`` lists a "choice"'s values."""

    name: str
    kind: str
    default: Any
    description: str
    low: float | None = None
    high: float | None = None
    choices: tuple[Any, ...] = ()


@dataclass(frozen=True)
class PatternSpec:
    """A pattern family: ``function(n=..., **parameters) -> (n, n, n) int8``."""

    name: str
    function: Callable[..., np.ndarray]
    description: str
    parameters: tuple[PatternParameter, ...]


_AXIS_CHOICES = ("x", "y", "z")
_PERIODS = PatternParameter("periods", "int", 1, "motif repeats along each axis", 1, 8)


def _fraction(default: float, what: str, high: float = 1.0) -> PatternParameter:
    return PatternParameter("fraction", "float", default, what, 0.0, high)


def _choice(name: str, default: str, what: str, choices: tuple[str, ...]) -> PatternParameter:
    return PatternParameter(name, "choice", default, what, choices=choices)


#: Name -> PatternSpec of every pattern family (GUI order).
PATTERNS: dict[str, PatternSpec] = {
    spec.name: spec
    for spec in (
        PatternSpec(
            "layered",
            layered,
            "Laminate of alternating layers (transversely isotropic about the normal)",
            (
                _choice("normal", "z", "layer normal", _AXIS_CHOICES),
                _fraction(0.5, "phase-b layer fraction"),
                _PERIODS,
            ),
        ),
        PatternSpec(
            "fibers",
            fibers,
            "Straight fibres / rods along an axis on a square array",
            (
                _choice("axis", "z", "fibre direction", _AXIS_CHOICES),
                _fraction(0.3, "fibre volume fraction", _MAX_FIBER_FRACTION),
                _PERIODS,
                _choice("shape", "round", "fibre section", ("round", "square")),
            ),
        ),
        PatternSpec(
            "checkerboard",
            checkerboard,
            "3D checkerboard of cubes (cubic symmetry, fraction 1/2)",
            (_PERIODS,),
        ),
        PatternSpec(
            "spheres",
            spheres,
            "Spotted: spherical inclusions on a cubic lattice (cubic symmetry)",
            (
                _fraction(0.2, "inclusion volume fraction", np.pi / 6.0),
                _PERIODS,
                _choice("arrangement", "sc", "sphere lattice", ("sc", "bcc", "fcc")),
            ),
        ),
        PatternSpec(
            "lattice",
            lattice,
            "Cross / lattice of square bars along the chosen axes",
            (
                _fraction(0.3, "bar volume fraction"),
                _PERIODS,
                _choice("axes", "xyz", "bar directions", ("xyz", "xy", "xz", "yz")),
            ),
        ),
        PatternSpec(
            "random",
            random_pattern,
            "Random voxels or blobs (statistically isotropic)",
            (
                _fraction(0.5, "phase-b volume fraction"),
                PatternParameter("seed", "int", 0, "random seed", 0, 2**31 - 1),
                PatternParameter(
                    "correlation", "float", 0.0, "blob size (cell units, 0 = voxels)", 0.0, 0.25
                ),
            ),
        ),
    )
}


def make_pattern(name: str, n: int = 16, **params: Any) -> np.ndarray:
    """Build the pattern ``name`` of :data:`PATTERNS` on an n^3 grid (ValueError listing the
    valid names or parameters)."""
    if name not in PATTERNS:
        raise ValueError(f"unknown pattern {name!r}; choose one of {list(PATTERNS)}")
    spec = PATTERNS[name]
    allowed = {p.name for p in spec.parameters}
    unknown = set(params) - allowed
    if unknown:
        raise ValueError(
            f"unknown parameter(s) {sorted(unknown)} for pattern {name!r}; valid: {sorted(allowed)}"
        )
    return spec.function(n=n, **params)
