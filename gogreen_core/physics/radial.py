"""Radial terms of the SH-regularized Green's function (the brush falloff).

For a radial load g_ε with Fourier transform ĝ the kernel needs, per degree l,
``R_l(r) = ∫₀^∞ ĝ(k) j_l(kr) dk`` (even l, for G; paper Eq. 10) and
``ℛ_l(r) = ∫₀^∞ ĝ(k) j_l(kr) k dk`` (odd l, for ∇G; paper Eq. 12). All profiles are scale-free:
``R_l(r) = F_l(ρ)/ε``, ``ℛ_l(r) = F'_l(ρ)/ε²`` with ρ = r/ε, so their tables
(:mod:`~gogreen_core.physics.radial_tables`) do not depend on ε.

* :class:`GaussianRadial`: g_ε = exp(-r²/ε²)/(ε³π^{3/2}), ĝ = exp(-ε²k²/4) (paper Eq. 13).
* :class:`KelvinletRadial`: g_ε = 15ε⁴/(8π)(r²+ε²)^{-7/2} (de Goes & James 2017),
  ĝ(k) = (εk)² K₂(εk)/2; with GR 6.576.3,
  R_l = (√π/2) ρ^l Γ((l+5)/2) Γ((l+1)/2)/Γ(l+3/2) ₂F₁((l+5)/2, (l+1)/2; l+3/2; -ρ²)/ε and
  ℛ_l = √π ρ^l Γ(l/2+3) Γ(l/2+1)/Γ(l+3/2) ₂F₁(l/2+3, l/2+1; l+3/2; -ρ²)/ε².
* :class:`SplineRadial`: the artist's per-degree curves through control points.
* :class:`MultiscaleRadial`: a weighted sum of one shape at several radii.
"""

from __future__ import annotations

import hashlib
from abc import ABC, abstractmethod
from collections.abc import Iterable, Sequence
from typing import Any, Self, cast

import numpy as np
from scipy import special
from scipy.interpolate import CubicHermiteSpline, CubicSpline, PPoly

from gogreen_core.physics.radial_tables import DECAY, TABLE_DEGREE, cached_table
from gogreen_core.validation import check_choice, check_integer, check_number

__all__ = [
    "INTERPOLATIONS",
    "TABLE_DEGREE",
    "GaussianRadial",
    "KelvinletRadial",
    "MultiscaleRadial",
    "RadialProfile",
    "SplineRadial",
    "radial_from_dict",
]

#: Kinds of radial term: "R" (R_l, even l, for G) and "dR" (ℛ_l, odd l, for ∇G).
KINDS = ("R", "dR")


def _check_degree(kind: str, l: int) -> int:
    check_choice("radial kind", kind, KINDS)
    return check_integer("degree l", l, low=0)


class RadialProfile(ABC):
    """A radial load profile: gives R_l and ℛ_l for every degree the kernel needs."""

    #: Name used in JSON ("type") and the GUI.
    kind_name: str = ""

    def __init__(self, eps: float):
        self._eps = check_number("eps", eps, low=0.0, low_open=True)

    @property
    def eps(self) -> float:
        """Regularization radius ε (model units)."""
        return self._eps

    @abstractmethod
    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        """F_l(ρ) ("R") or F'_l(ρ) ("dR") at ρ = r/ε (any shape), float64."""

    def with_eps(self, eps: float) -> Self:
        """The same falloff shape with another radius ε (shares cached tables)."""
        clone = object.__new__(type(self))
        clone.__dict__.update(self.__dict__)
        clone._eps = check_number("eps", eps, low=0.0, low_open=True)
        return clone

    def as_value(self) -> Self:
        """This shape at ε = 1 (what settings hold and compare by content)."""
        return self if self._eps == 1.0 else self.with_eps(1.0)

    @abstractmethod
    def table_key(self) -> tuple[Any, ...]:
        """Hashable identity of the shape (not ε): equal keys give equal tables."""

    def table(self, kind: str, degrees: Iterable[int]) -> np.ndarray:
        """Tables (n_degrees, TABLE_SEGMENTS, TABLE_DEGREE+1) of :func:`radial_table`."""
        return np.stack([cached_table(self.table_key(), kind, int(l), self) for l in degrees])

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description; :func:`radial_from_dict` inverts it."""

    def __eq__(self, other: object) -> bool:
        """Equal by content: the same kind, ε and shape (:meth:`table_key`)."""
        if not isinstance(other, RadialProfile):
            return NotImplemented
        same = type(other) is type(self) and other.eps == self.eps
        return same and other.table_key() == self.table_key()

    def __hash__(self) -> int:
        return hash((self.eps, self.table_key()))

    def __repr__(self) -> str:
        return f"{type(self).__name__}(eps={self._eps:g})"


class _ClosedFormRadial(RadialProfile):
    def table_key(self) -> tuple[Any, ...]:
        return (self.kind_name,)

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.kind_name, "eps": self._eps}


class GaussianRadial(_ClosedFormRadial):
    """Gaussian load: the paper's Eq. 13 (regularized ₁F̃₁); scipy's ₁F₁ stays accurate at
    large negative arguments (~1e-13 against quadrature for l ≤ 31, ρ ≤ 10⁵)."""

    kind_name = "gaussian"

    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        l = _check_degree(kind, l)
        rho = np.asarray(rho, dtype=np.float64)
        a, c = ((l + 1) / 2, np.sqrt(np.pi) / 2) if kind == "R" else (l / 2 + 1, np.sqrt(np.pi))
        scale = c * special.gamma(a) / special.gamma(l + 1.5)
        return cast(np.ndarray, scale * rho**l * special.hyp1f1(a, l + 1.5, -(rho**2)))


class KelvinletRadial(_ClosedFormRadial):
    """Regularized Kelvinlet load: with an isotropic material the kernel is de Goes & James'
    closed form u = [(a-b)/r_ε I + b/r_ε³ r rᵀ + a ε²/(2 r_ε³) I] f, a = 1/(4πμ), b = a/(4(1-ν))."""

    kind_name = "kelvinlet"

    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        l = _check_degree(kind, l)
        rho = np.asarray(rho, dtype=np.float64)
        if kind == "R":
            a, b, c = (l + 5) / 2, (l + 1) / 2, np.sqrt(np.pi) / 2
        else:
            a, b, c = l / 2 + 3, l / 2 + 1, np.sqrt(np.pi)
        scale = c * special.gamma(a) * special.gamma(b) / special.gamma(l + 1.5)
        return cast(np.ndarray, scale * rho**l * special.hyp2f1(a, b, l + 1.5, -(rho**2)))


#: How a spline falloff passes through its control points: ``"monotone"`` (new curves,
#: :func:`monotone_hermite`), or ``"cubic"``, the not-a-knot C² spline of files saved before
#: (no ``"interpolation"`` key), kept for them; it overshoots and rings, which a stroke shows
#: as lines along its rim (``benchmarks/falloff_striations.py``).
INTERPOLATIONS = ("monotone", "cubic")

#: Points on each side whose polynomial gives a point's slope (4th-order slopes).
_STENCIL = 2


def local_slopes(rho: np.ndarray, value: np.ndarray) -> np.ndarray:
    """At each point (n ≥ 3), the slope of the polynomial through it and its
    :data:`_STENCIL` neighbours on each side (shifted inwards at the ends): 4th-order accurate.
    Lagrange's formula for all points at once (a falloff reset rebuilds 30 curves on the GUI
    thread)."""
    rho = np.asarray(rho, dtype=np.float64)
    value = np.asarray(value, dtype=np.float64)
    n = len(rho)
    width = min(2 * _STENCIL + 1, n)
    point = np.arange(n)
    start = np.clip(point - _STENCIL, 0, n - width)
    window = start[:, None] + np.arange(width)  # (n, width) indices of each point's stencil
    x, y = rho[window], value[window]
    at = point - start  # the point's place in its stencil
    own = np.arange(width)[None, :] == at[:, None]  # (n, width)
    x_at = rho[:, None, None]
    # (x_i − x_k) / (x_j − x_k) over k ∉ {i, j}: the derivative at x_i of the j-th Lagrange
    # basis polynomial, ℓ_j′(x_i) = Π_k≠i,j (x_i − x_k) / Π_k≠j (x_j − x_k)
    skip = np.eye(width, dtype=bool)[None] | own[:, None, :]  # (n, j, k)
    gap_jk = np.where(skip, 1.0, x[:, :, None] - x[:, None, :])
    ratio = np.where(skip, 1.0, (x_at - x[:, None, :]) / gap_jk)
    gap_ji = np.where(own, 1.0, x - rho[:, None])
    weight = np.prod(ratio, axis=2) / gap_ji
    # ℓ_i′(x_i) = Σ_k≠i 1 / (x_i − x_k)
    weight[own] = np.sum(np.where(own, 0.0, 1.0 / np.where(own, 1.0, rho[:, None] - x)), axis=1)
    return np.asarray(np.sum(weight * y, axis=1))


def monotone_hermite(rho: np.ndarray, value: np.ndarray) -> CubicHermiteSpline:
    """The C¹ piecewise cubic through (ρ_i, value_i) (n ≥ 3), monotone on every interval: the
    :func:`local_slopes` limited as Fritsch & Carlson (1980) do (0 at a local extremum, else at
    most 3× the smaller neighbouring secant). Moving a point changes the curve near it alone.

    Not SciPy's PCHIP (2nd-order slopes): its curvature jumps at every control point (max
    |F″ − G″| on R₀ 1.41 against 0.05 here), which shows in a stroke's shading, and a tri-scale
    grab on it strains past the safety bound (2.03 against 1.61)."""
    rho = np.asarray(rho, dtype=np.float64)
    value = np.asarray(value, dtype=np.float64)
    secant = np.diff(value) / np.diff(rho)
    left = np.concatenate([secant[:1], secant])
    right = np.concatenate([secant, secant[-1:]])
    sign = np.sign(right)
    bound = 3.0 * np.minimum(np.abs(left), np.abs(right))
    limited = sign * np.minimum(np.maximum(sign * local_slopes(rho, value), 0.0), bound)
    return CubicHermiteSpline(rho, value, np.where(left * right > 0, limited, 0.0))


def interpolant(interpolation: str, rho: np.ndarray, value: np.ndarray) -> PPoly:
    """The curve through the control points (ρ (n,) increasing, value (n,)) by
    ``interpolation`` (one of :data:`INTERPOLATIONS`)."""
    if check_choice("spline interpolation", interpolation, INTERPOLATIONS) == "monotone":
        return monotone_hermite(rho, value)
    return CubicSpline(rho, value, bc_type="not-a-knot")


#: Default control abscissae (ρ = r/ε) of a spline falloff: dense where the falloff bends.
DEFAULT_SPLINE_RHO = np.array(
    [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0, 10.0]
)


class SplineRadial(RadialProfile):
    """Per-degree curves through control points (ρ_i, F(ρ_i)), ρ = r/ε, keyed by (kind, l)
    ("R" for R_l, even l; "dR" for ℛ_l, odd l), interpolated by :attr:`interpolation` (one of
    :data:`INTERPOLATIONS`; ``"cubic"`` unless given, as files without the key mean).

    Control abscissae start at ρ = 0 and increase; for l ≥ 1 the value at ρ = 0 is pinned to 0
    (R_l(0) = 0, as the paper does). Beyond the last point ρ_n the curve decays as
    F(ρ_n)(ρ_n/ρ)^p (p = 1 for R, 2 for ℛ). An immutable value compared by content: an edit
    makes a new one (:meth:`with_curves`, ...) and bumps :attr:`version`; tables are keyed by a
    digest of the points.
    """

    kind_name = "spline"

    def __init__(
        self,
        eps: float,
        curves: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]],
        interpolation: str = "cubic",
    ):
        super().__init__(eps)
        self._interpolation = interpolation
        self._curves: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]] = {}
        self._splines: dict[tuple[str, int], PPoly] = {}
        self._digest: str | None = None
        self._version = 0
        if not curves:
            raise ValueError("a spline falloff needs at least one curve")
        for (kind, l), (rho, value) in curves.items():
            self._store(kind, l, rho, value)  # (its interpolant refuses a bad interpolation)

    @classmethod
    def from_profile(
        cls,
        profile: RadialProfile,
        l_max: int,
        rho: np.ndarray | None = None,
        interpolation: str = "monotone",
    ) -> SplineRadial:
        """Sample ``profile`` at control points ``rho`` (default :data:`DEFAULT_SPLINE_RHO`)
        for every degree a kernel of ``l_max`` needs (even l ≤ l_max, odd l ≤ l_max + 1)."""
        rho = DEFAULT_SPLINE_RHO if rho is None else np.asarray(rho, dtype=np.float64)
        curves = {}
        for l in range(0, l_max + 1, 2):
            curves[("R", l)] = (rho, profile.dimensionless("R", l, rho))
        for l in range(1, l_max + 2, 2):
            curves[("dR", l)] = (rho, profile.dimensionless("dR", l, rho))
        return cls(profile.eps, curves, interpolation)

    # -- editing ----------------------------------------------------------------------------
    @property
    def interpolation(self) -> str:
        """How the curves pass through their points (see :data:`INTERPOLATIONS`)."""
        return self._interpolation

    def with_interpolation(self, interpolation: str) -> SplineRadial:
        """The same control points through another interpolant (a new value)."""
        clone = SplineRadial(self.eps, self._curves, interpolation)
        clone._version = self._version + 1
        return clone

    @property
    def version(self) -> int:
        """Incremented by every edit (an edited value has its source's version + 1)."""
        return self._version

    def curve_keys(self) -> list[tuple[str, int]]:
        """(kind, degree) of every stored curve, sorted."""
        return sorted(self._curves)

    def curve(self, kind: str, l: int) -> tuple[np.ndarray, np.ndarray]:
        """Copies of the control points (ρ (n,), value (n,)) of one curve."""
        rho, value = self._curves[self._key(kind, l)]
        return rho.copy(), value.copy()

    def with_curves(
        self, curves: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]] | SplineRadial
    ) -> SplineRadial:
        """This falloff with the given curves (or another spline's, with its interpolation)
        replacing or adding to its own (a new value; the others are kept)."""
        if isinstance(curves, SplineRadial):
            if curves.interpolation != self.interpolation:
                return self.with_interpolation(curves.interpolation).with_curves(curves)
            curves = curves._curves
        clone = object.__new__(SplineRadial)
        clone.__dict__.update(self.__dict__)
        # the other curves' (read-only) points and splines are shared, not rebuilt
        clone._curves, clone._splines = dict(self._curves), dict(self._splines)
        for (kind, l), (rho, value) in curves.items():
            clone._store(kind, l, rho, value)
        clone._version = self._version + 1
        return clone

    def with_point_moved(
        self, kind: str, l: int, index: int, rho: float, value: float
    ) -> SplineRadial:
        """This falloff with control point ``index`` at (rho, value), between its neighbours."""
        xs, ys = self.curve(kind, l)
        xs[index], ys[index] = rho, value
        return self.with_curves({(kind, l): (xs, ys)})

    def with_point_added(
        self, kind: str, l: int, rho: float, value: float
    ) -> tuple[SplineRadial, int]:
        """This falloff with a control point inserted, and the point's index."""
        xs, ys = self.curve(kind, l)
        index = int(np.searchsorted(xs, rho))
        return self.with_curves(
            {(kind, l): (np.insert(xs, index, rho), np.insert(ys, index, value))}
        ), index

    def without_point(self, kind: str, l: int, index: int) -> SplineRadial:
        """This falloff without control point ``index`` (not the one at ρ = 0)."""
        xs, ys = self.curve(kind, l)
        if index == 0 or index % len(xs) == 0:
            raise ValueError("the control point at rho = 0 cannot be removed")
        if len(xs) <= 3:
            raise ValueError("a falloff curve needs at least 3 control points")
        return self.with_curves({(kind, l): (np.delete(xs, index), np.delete(ys, index))})

    def _key(self, kind: str, l: int) -> tuple[str, int]:
        l = _check_degree(kind, l)
        key = (kind, l)
        if key not in self._curves:
            have = ", ".join(f"{k}{d}" for k, d in sorted(self._curves))
            raise ValueError(f"spline falloff has no curve {kind}{l} (it has {have})")
        return key

    def _store(self, kind: str, l: int, rho: np.ndarray, value: np.ndarray) -> None:
        l = _check_degree(kind, l)
        rho = np.array(rho, dtype=np.float64)
        value = np.array(value, dtype=np.float64)
        name = f"falloff curve {kind}{l}"
        if rho.ndim != 1 or rho.shape != value.shape:
            raise ValueError(f"{name}: rho and value must be 1-D of equal length")
        if len(rho) < 3:
            raise ValueError(f"{name}: needs at least 3 control points (got {len(rho)})")
        if not (np.all(np.isfinite(rho)) and np.all(np.isfinite(value))):
            raise ValueError(f"{name}: control points must be finite")
        if rho[0] != 0.0:
            raise ValueError(f"{name}: the first control point must be at rho = 0 (got {rho[0]})")
        if np.any(np.diff(rho) <= 0):
            raise ValueError(f"{name}: control abscissae rho must be strictly increasing")
        if l >= 1:
            value[0] = 0.0  # R_l(0) = 0 for l >= 1 (paper); pinned, not an error
        rho.setflags(write=False)
        value.setflags(write=False)
        self._curves[(kind, l)] = (rho, value)
        self._splines[(kind, l)] = interpolant(self._interpolation, rho, value)
        self._digest = None

    # -- evaluation --------------------------------------------------------------------------
    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        key = self._key(kind, l)
        xs, ys = self._curves[key]
        rho = np.asarray(rho, dtype=np.float64)
        out = np.empty_like(rho)
        inside = rho <= xs[-1]
        out[inside] = self._splines[key](rho[inside])
        out[~inside] = ys[-1] * (xs[-1] / rho[~inside]) ** DECAY[kind]
        return out

    def table_key(self) -> tuple[Any, ...]:
        # by content, never by id(): a new profile may reuse a dead one's id (and its table)
        if self._digest is None:
            digest = hashlib.sha256(f"{self._interpolation};".encode())
            for (kind, l), (rho, value) in sorted(self._curves.items()):
                digest.update(f"{kind}{l}:{len(rho)};".encode())
                digest.update(rho.tobytes())
                digest.update(value.tobytes())
            self._digest = digest.hexdigest()
        return ("spline", self._digest)

    # -- serialization -----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        data = {
            "type": "spline",
            "eps": self.eps,
            "curves": [
                {"kind": k, "degree": l, "rho": rho.tolist(), "value": value.tolist()}
                for (k, l), (rho, value) in sorted(self._curves.items())
            ],
        }
        if self._interpolation != "cubic":  # absent: the cubic of files written before
            data["interpolation"] = self._interpolation
        return data


class MultiscaleRadial(RadialProfile):
    """Weighted sum of one falloff shape at several radii (Kelvinlets' multi-scale brushes):
    F_l(ρ) = Σ_k w_k s_k^{-p} F_l^base(ρ/s_k), p = 1 for R_l, 2 for ℛ_l; :meth:`biscale` and
    :meth:`triscale` (de Goes & James 2017, Sec. 5) cancel the leading far-field terms. One
    table serves the sum."""

    kind_name = "multiscale"

    def __init__(self, base: RadialProfile, scales: Sequence[float], weights: Sequence[float]):
        if not isinstance(base, RadialProfile) or isinstance(base, MultiscaleRadial):
            raise ValueError("the base of a multi-scale falloff must be a single RadialProfile")
        scales = tuple(float(v) for v in scales)
        weights = tuple(float(v) for v in weights)
        if len(scales) != len(weights) or not scales:
            raise ValueError("multi-scale falloff needs as many weights as scales (at least one)")
        if not all(np.isfinite(v) and v > 0 for v in scales):
            raise ValueError(f"multi-scale falloff scales must be finite and > 0 (got {scales})")
        if not all(np.isfinite(v) for v in weights):
            raise ValueError(f"multi-scale falloff weights must be finite (got {weights})")
        super().__init__(base.eps)
        self._base, self._scales, self._weights = base, scales, weights

    @classmethod
    def biscale(cls, base: RadialProfile, ratio: float = 1.25) -> MultiscaleRadial:
        """u_ε − u_{ε·ratio}. The default 1.25 is this project's choice, not a standard:
        Blender's Elastic Deform brush scales each radius by 2 (ε, 2ε, 4ε), libigl's by 1.1."""
        return cls(base, (1.0, ratio), (1.0, -1.0))

    @classmethod
    def triscale(
        cls, base: RadialProfile, ratio: float = 1.25, first: float = 1.0
    ) -> MultiscaleRadial:
        """u_ε1 − (ε3² − ε1²)/(ε3² − ε2²) u_ε2 + (ε2² − ε1²)/(ε3² − ε2²) u_ε3, ε_k = ε first
        ratio^(k-1). The default ratio 1.25 is this project's choice (Blender uses 2, libigl 1.1).
        """
        e1, e2, e3 = first, first * ratio, first * ratio * ratio
        w2 = -(e3**2 - e1**2) / (e3**2 - e2**2)
        w3 = (e2**2 - e1**2) / (e3**2 - e2**2)
        return cls(base, (e1, e2, e3), (1.0, w2, w3))

    @classmethod
    def local(cls, base: RadialProfile) -> MultiscaleRadial:
        """Key 1's grab: tri-scale at 0.4, 0.8, 1.6 ε (ratio 2, Blender's), so that what moves
        by a tenth of the motion or more is the brush circle (triscale: 1.6 ε; Gaussian: 11 ε)."""
        return cls.triscale(base, 2.0, 0.4)

    @property
    def base(self) -> RadialProfile:
        return self._base

    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        rho = np.asarray(rho, dtype=np.float64)
        p = DECAY[kind]
        return cast(
            np.ndarray,
            sum(
                w * s**-p * self._base.dimensionless(kind, l, rho / s)
                for s, w in zip(self._scales, self._weights, strict=True)
            ),
        )

    def table_key(self) -> tuple[Any, ...]:
        return ("multiscale", self._base.table_key(), self._scales, self._weights)

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": self.kind_name,
            "eps": self.eps,
            "base": self._base.to_dict(),
            "scales": list(self._scales),
            "weights": list(self._weights),
        }


def radial_from_dict(data: dict[str, Any]) -> RadialProfile:
    """Rebuild a profile from :meth:`RadialProfile.to_dict` output."""
    if not isinstance(data, dict) or "type" not in data or "eps" not in data:
        raise ValueError("a falloff description needs 'type' and 'eps'")
    kind = data["type"]
    if kind == "gaussian":
        return GaussianRadial(data["eps"])
    if kind == "kelvinlet":
        return KelvinletRadial(data["eps"])
    if kind == "multiscale":
        try:
            base = radial_from_dict(data["base"])
            return MultiscaleRadial(base.with_eps(data["eps"]), data["scales"], data["weights"])
        except (KeyError, TypeError) as exc:
            raise ValueError(f"malformed multi-scale falloff description: {exc}") from None
    if kind == "spline":
        try:
            curves = {
                (c["kind"], int(c["degree"])): (np.asarray(c["rho"]), np.asarray(c["value"]))
                for c in data["curves"]
            }
        except (KeyError, TypeError) as exc:
            raise ValueError(f"malformed spline falloff description: {exc}") from None
        return SplineRadial(data["eps"], curves, data.get("interpolation", "cubic"))
    raise ValueError(
        f"unknown falloff type {kind!r} (expected gaussian, kelvinlet, spline or multiscale)"
    )
