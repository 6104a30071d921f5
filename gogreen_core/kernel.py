"""The regularized Green's function of any linear elastic material (Chen & Desbrun 2022).

G(x) = 1/(2π²) Σ_{l even} i^l R_l(r) Σ_m Y_lm(x̂) P_lm              (paper Eq. 10)
∂_p G(x) = 1/(2π²) Σ_{l odd} i^{l+1} ℛ_l(r) Σ_m Y_lm(x̂) 𝒫_lm,p     (paper Eq. 12)

with M(ξ)_ik = C_ijkl ξ_j ξ_l, P_lm = ∫_S² M(ξ̂)⁻¹ Y_lm(ξ̂) dS and 𝒫_lm,p = ∫_S² M⁻¹ Y_lm ξ̂_p dS in
the real SH basis of ``sph.py`` (the addition theorem makes the real basis exact, so everything
stays real). The material matrices are integrated once, by the paper's Lebedev rule where M⁻¹ is
smooth and by a product rule graded toward the material's axis where it is sharply peaked
(:func:`material_rule`); R_l and ℛ_l come
from the radial profile's tables (``radial.py``); evaluation is the numba kernel of
``_expansion.py``. G is truncated at even l ≤ l_max and ∇G at odd l ≤ l_max + 1.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from functools import lru_cache

import numpy as np
from scipy.integrate import lebedev_rule

from gogreen_core._expansion import SEGMENT_DEGREE, expand, generic_marker, stream
from gogreen_core._unrolled import UNROLLED_L_MAX, unrolled_angular
from gogreen_core.material import Material
from gogreen_core.radial import TABLE_DEGREE, GaussianRadial, RadialProfile
from gogreen_core.sph import legendre_recurrence, real_sph_harm
from gogreen_core.validation import ParameterError, check_number

__all__ = [
    "COORDINATE_LIMIT",
    "L_MAX_LIMIT",
    "GreenKernel",
    "StreamlineOverflow",
    "lebedev_points",
    "material_rule",
    "prepare_degree",
]

#: Highest supported truncation degree.
L_MAX_LIMIT = 60


class StreamlineOverflow(ValueError):
    """The streamlines would move a point to infinity (nothing was moved)."""


#: Lebedev rule used for the material matrices when M(ξ̂)⁻¹ is smooth enough for it (5,810
#: nodes, exact to degree 131: the paper's).
QUADRATURE_ORDER = 131
#: Lower Lebedev rule whose disagreement with QUADRATURE_ORDER on the low moments of M⁻¹ measures
#: M⁻¹'s content between degrees ~70 and 131, which is what would alias into the coefficients of
#: degree ≤ 61 under the 131 rule.
CHECK_ORDER = 71
#: Relative accuracy asked of the material matrices (against their largest entry).
QUADRATURE_RTOL = 1e-11
#: Default error target of :meth:`GreenKernel.streamlines`, relative to the motion scale.
STREAMLINE_TOLERANCE = 1e-4


@lru_cache(maxsize=4)
def lebedev_points(order: int = QUADRATURE_ORDER) -> tuple[np.ndarray, np.ndarray]:
    """Lebedev nodes (n, 3) on the unit sphere and weights (n,) summing to 4π (read-only)."""
    nodes, weights = lebedev_rule(order)
    nodes = np.ascontiguousarray(nodes.T)
    nodes.setflags(write=False)
    weights.setflags(write=False)
    return nodes, weights


def _low_moments(material: Material, nodes: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """∫ M⁻¹ ξ̂^α dS for the monomials of degree ≤ 2 (10, 3, 3): the error indicator."""
    m_inv = np.linalg.inv(material.acoustic_tensor(nodes))
    x, y, z = nodes.T
    mono = np.stack([np.ones_like(x), x, y, z, x * x, y * y, z * z, x * y, x * z, y * z])
    return ((mono * weights) @ m_inv.reshape(len(nodes), 9)).reshape(10, 3, 3)


def _material_frame(material: Material) -> np.ndarray:
    """Rotation (3, 3) whose last column is the material's most distinct axis: the eigenvector
    of A_ij = C_ikjk whose eigenvalue stands farthest (in ratio) from the other two. Stiff
    fibres along it put the ridge of M⁻¹ on the frame's equator, a stiff plane normal to it puts
    the peaks of M⁻¹ at the frame's poles: both where the product rule grades its nodes."""
    values, vectors = np.linalg.eigh(np.einsum("ikjk->ij", material.tensor))
    logs = np.log(np.maximum(values, values[-1] * 1e-300))
    axis = 0 if logs[1] - logs[0] > logs[2] - logs[1] else 2
    others = [k for k in range(3) if k != axis]
    frame = vectors[:, [*others, axis]]
    return frame if np.linalg.det(frame) > 0 else frame * np.array([-1.0, 1.0, 1.0])


def _product_rule(
    l_max: int, level: int, frame: np.ndarray, finest: float
) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre in the polar angle θ × trapezoid in φ, in ``frame``: nodes (n, 3) and
    weights (n,) summing to 4π.

    θ panels: uniform ones with enough points for Y_lm up to l_max + 1 (GL with p points
    resolves e^{ilθ} on a panel of width h for p ≳ lh/2 + 8), refined geometrically (ratio 2)
    toward the equator and the poles down to width ``finest``, where the integrand M⁻¹ of a
    strongly anisotropic material has its ridges and peaks: composite Gauss–Legendre on
    geometrically graded panels converges exponentially however sharp the feature. ``level``
    ≥ 0 raises the points per panel and in φ.
    """
    coarse_points, fine_points = 16 + 4 * level, 8 + 4 * level
    n_uniform = int(np.ceil(np.pi * (l_max + 2) / (4 * (coarse_points - 8))))
    uniform_width = np.pi / (2 * n_uniform)
    edges = set(np.linspace(0.0, np.pi, 2 * n_uniform + 1).tolist())
    width = finest
    while width < uniform_width / 2:
        edges.update((width, np.pi / 2 - width, np.pi / 2 + width, np.pi - width))
        width *= 2.0
    edges = np.array(sorted(edges))
    thetas, theta_weights = [], []
    for points in (coarse_points, fine_points):
        lo, hi = edges[:-1], edges[1:]
        pick = ((hi - lo) > 0.75 * uniform_width) == (points == coarse_points)
        lo, hi = lo[pick, None], hi[pick, None]
        gx, gw = np.polynomial.legendre.leggauss(points)
        thetas.append((lo + 0.5 * (hi - lo) * (gx + 1)).ravel())
        theta_weights.append((0.5 * (hi - lo) * gw).ravel())
    theta = np.concatenate(thetas)
    w_theta = np.concatenate(theta_weights) * np.sin(theta)
    n_phi = 2 * (l_max + 2) + 24 * (level + 1)
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    sin_t = np.sin(theta)[:, None]
    local = np.stack(
        [sin_t * np.cos(phi), sin_t * np.sin(phi), np.cos(theta)[:, None] + 0 * phi], axis=-1
    ).reshape(-1, 3)
    weights = np.repeat(w_theta, n_phi) * (2 * np.pi / n_phi)
    return local @ frame.T, weights


def material_rule(
    material: Material, l_max: int, rtol: float = QUADRATURE_RTOL
) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature nodes (n, 3) and weights (n,) on the unit sphere for the material matrices
    P_lm = ∫ M(ξ̂)⁻¹ Y_lm dS of truncation ``l_max``, accurate to ``rtol`` (relative).

    M⁻¹ is smooth for mild anisotropy, and the paper's Lebedev rule (order 131) serves; for
    strong anisotropy it is sharply peaked (fibres at contrast 10⁴: a ridge 0.016 rad wide, and
    the Lebedev rule's l = 0 coefficient is off by 1.5e-3). The Lebedev rule is kept when a lower
    one (order 71) agrees with it on the moments of M⁻¹ up to degree 2, i.e. when M⁻¹ has no
    content the rule would alias; otherwise a product rule graded toward the material's axis
    (:func:`_product_rule`) is refined until two successive levels agree to ``rtol``, and the
    coarser of the two is returned (at most four levels: past them the finest serves).
    """
    nodes, weights = lebedev_points()
    reference = _low_moments(material, nodes, weights)
    scale = np.abs(reference).max()
    check = _low_moments(material, *lebedev_points(CHECK_ORDER))
    if np.abs(check - reference).max() <= rtol * scale:
        return nodes, weights
    frame = _material_frame(material)
    stiffness = np.linalg.eigvalsh(material.voigt)
    finest = min(0.05, 0.1 * np.sqrt(stiffness[0] / stiffness[-1]))
    coarse = _product_rule(l_max, 0, frame, finest)
    coarse_moments = _low_moments(material, *coarse)
    for level in range(1, 4):
        fine = _product_rule(l_max, level, frame, finest)
        fine_moments = _low_moments(material, *fine)
        if np.abs(fine_moments - coarse_moments).max() <= rtol * scale:
            return coarse  # two levels agree: the cheaper one is accurate
        coarse, coarse_moments = fine, fine_moments
    return coarse


def _parity_ranges(l_max: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(first, last) degree of each parity for truncation ``l_max``: even l ≤ l_max for G,
    odd l ≤ l_max + 1 for ∇G."""
    return (0, l_max - l_max % 2), (1, l_max + 1 - l_max % 2)


def prepare_degree(l_max: int) -> float:
    """Compile (or load from numba's disk cache) the shipped angular kernels that vector
    and affine loads of truncation degree ``l_max`` use; returns the seconds it took.

    Thread safe and runs no parallel code, so it can run on a background thread while strokes
    evaluate (numba's workqueue threading layer forbids concurrent parallel launches).
    """
    start = time.perf_counter()
    for l_first, l_last in _parity_ranges(l_max):
        if l_last <= UNROLLED_L_MAX:
            unrolled_angular(l_first, l_last)
    return time.perf_counter() - start


#: Largest coordinate magnitude of points, offsets and centers: differences of two such values
#: and their norms stay finite, so every point within it, however far, gets a finite value (the
#: far field decays as 1/r, 1/r² for gradients). Beyond it a ParameterError names the input.
COORDINATE_LIMIT = 1e300


def _finite_array(name: str, value, shape: tuple[int, ...]) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != shape:
        raise ParameterError(name, f"{name} must have shape {shape} (got {arr.shape})")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(name, f"{name} must be finite")
    return arr


def _within_limit(name: str, arr: np.ndarray) -> np.ndarray:
    if arr.size and np.abs(arr).max() > COORDINATE_LIMIT:
        raise ParameterError(
            name,
            f"{name} has a coordinate of magnitude {np.abs(arr).max():.3g}, beyond the "
            f"supported {COORDINATE_LIMIT:g}",
        )
    return arr


def _points(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ParameterError(name, f"{name} must have shape (N, 3) (got {arr.shape})")
    if not np.isfinite(arr).all():
        raise ParameterError(name, f"{name} contain non-finite values (NaN or inf)")
    return np.ascontiguousarray(_within_limit(name, arr))


def _load_coefficients(name: str, coeffs: np.ndarray) -> np.ndarray:
    if not np.isfinite(coeffs).all():
        raise ParameterError(
            name, f"{name} is too large for this material: its expansion overflows"
        )
    return coeffs


def _evaluation_tables(tables: np.ndarray) -> np.ndarray:
    """(n_degrees, S, D+1), C-contiguous: the layout ``_expansion._radial`` reads (the D+1
    coefficients of one degree's segment contiguous)."""
    return np.ascontiguousarray(tables, dtype=np.float64)


# _expansion unrolls the segment polynomial for this degree
assert TABLE_DEGREE == SEGMENT_DEGREE


def _checked_weights(degree_weights: Sequence[float] | None, l_max: int) -> np.ndarray:
    """Degree weights (l_max + 1,), read-only: all ones for None."""
    if degree_weights is None:
        weights = np.ones(l_max + 1)
    else:
        weights = np.array(degree_weights, dtype=np.float64)
        if weights.shape != (l_max + 1,):
            raise ValueError(
                f"degree_weights must have l_max + 1 = {l_max + 1} values "
                f"(got shape {weights.shape})"
            )
        if not np.all(np.isfinite(weights)):
            raise ValueError("degree_weights must be finite")
    weights.setflags(write=False)
    return weights


class _Parity:
    """Packed material coefficients of one parity (even: G, odd: ∇G)."""

    def __init__(self, l_first: int, l_last: int, matrices: np.ndarray, base: np.ndarray):
        self.l_first = l_first
        self.l_last = l_last
        self.degrees = list(range(l_first, l_last + 1, 2))
        self.matrices = matrices  # (n_terms, 3, 3) or (n_terms, 3, 3, 3)
        self.base = base  # (l_last+1,) int64, row of Y_l,-l

    def angular(self, n_out: int) -> tuple[object, bool]:
        """(angular kernel, whether to use it) for ``n_out`` outputs: the kernel generated for
        this degree (``_unrolled``) for the three outputs of vector and affine loads up to
        ``UNROLLED_L_MAX``, else the drivers' generic ``_angular``. The choice depends on
        nothing else, so results are reproducible bit for bit."""
        if n_out == 3 and self.l_last <= UNROLLED_L_MAX:
            return unrolled_angular(self.l_first, self.l_last), True
        return generic_marker, False


class GreenKernel:
    """Regularized Green's function G and its gradient for one material and falloff.

    Parameters
    ----------
    material : Material
    l_max : int, 0 ≤ l_max ≤ 60
        Truncation degree: G uses even l ≤ l_max, ∇G odd l ≤ l_max + 1.
    radial : RadialProfile, default ``GaussianRadial(1.0)``
        The load profile (falloff), which also sets the radius ε.
    degree_weights : sequence of l_max + 1 floats, optional
        Scales the degree-l term of G (the paper's wrinkle brush: truncation or reweighting).
        The odd degree l of ∇G uses ``degree_weights[l - 1]``, so zero weights above degree L
        make ∇G the gradient truncated as G is. Default all ones.

    Building a kernel takes milliseconds (the radial tables are cached per profile shape), so
    rebuild it whenever the material changes; :meth:`with_radial` changes the falloff or the
    radius without recomputing the material matrices.
    """

    def __init__(
        self,
        material: Material,
        l_max: int = 8,
        radial: RadialProfile | None = None,
        degree_weights: Sequence[float] | None = None,
    ):
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material (got {type(material).__name__})")
        if isinstance(l_max, bool) or not isinstance(l_max, (int, np.integer)):
            raise ValueError(f"l_max must be an integer (got {l_max!r})")
        l_max = int(l_max)
        if not 0 <= l_max <= L_MAX_LIMIT:
            raise ValueError(f"l_max must lie in [0, {L_MAX_LIMIT}] (got {l_max})")
        radial = GaussianRadial(1.0) if radial is None else radial
        if not isinstance(radial, RadialProfile):
            raise ValueError(f"radial must be a RadialProfile (got {type(radial).__name__})")
        weights = _checked_weights(degree_weights, l_max)
        self._material = material
        self._l_max = l_max
        self._weights = weights
        self._sums = self._material_sums(material, l_max)
        self._even, self._odd = self._pack(self._sums, l_max, weights)
        rec = legendre_recurrence(l_max + 1)
        self._recurrence = (
            np.ascontiguousarray(rec.qmm),
            np.ascontiguousarray(rec.a),
            np.ascontiguousarray(rec.b),
        )
        self._set_radial(radial)

    # -- precompute --------------------------------------------------------------------------
    @staticmethod
    def _material_sums(material: Material, l_max: int) -> tuple[np.ndarray, np.ndarray]:
        """Σ_q w_q Y_lm(ξ_q) M⁻¹(ξ_q) (even l, (n_even, 9)) and the same times ξ_q,p (odd l,
        (n_odd, 27)): the quadrature of paper Eq. 10 and 12, before signs and weights."""
        nodes, qw = material_rule(material, l_max)
        (_, even_last), (_, odd_last) = _parity_ranges(l_max)
        even_rows = [c for l in range(0, even_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
        odd_rows = [c for l in range(1, odd_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
        # one product per parity, on the rows of the (terms, n) harmonics (contiguous rows,
        # cheap to gather), in chunks of nodes that bound the harmonics to ~64 MB.
        even_sum, odd_sum = 0.0, 0.0
        chunk = max(256, 8_000_000 // (l_max + 2) ** 2)
        for start in range(0, len(nodes), chunk):
            part = nodes[start : start + chunk]
            m_inv = np.linalg.inv(material.acoustic_tensor(part))
            m_inv *= qw[start : start + chunk, None, None]
            flat = m_inv.reshape(len(part), 9)
            grad_flat = (m_inv[:, :, :, None] * part[:, None, None, :]).reshape(len(part), 27)
            rows = real_sph_harm(part, l_max + 1).T  # ((L+1)², n), C-contiguous
            even_sum = even_sum + rows[even_rows] @ flat
            odd_sum = odd_sum + rows[odd_rows] @ grad_flat
        return even_sum, odd_sum

    @staticmethod
    def _pack(
        sums: tuple[np.ndarray, np.ndarray],
        l_max: int,
        weights: np.ndarray,
        output_maps: np.ndarray | None = None,
    ) -> tuple[_Parity, _Parity]:
        """The even and odd packed coefficients: the sums times i^l (even l) or i^(l+1) (odd
        l), both real, the 1/(2π²) and the degree weight, then the degree's output map."""

        def pack(l_first: int, l_last: int, sums: np.ndarray, shape: tuple) -> _Parity:
            base = np.full(l_last + 1 if l_last >= 0 else 1, -1, dtype=np.int64)
            factors, offset = [], 0
            for l in range(l_first, l_last + 1, 2):
                base[l] = offset
                offset += 2 * l + 1
                sign = (-1.0) ** ((l + (l % 2)) // 2)
                weight = weights[l] if l % 2 == 0 else weights[l - 1]
                factors.extend([sign * weight / (2 * np.pi**2)] * (2 * l + 1))
            mats = (sums * np.asarray(factors)[:, None]).reshape((offset, *shape))
            if output_maps is not None:
                for l in range(l_first, l_last + 1, 2):
                    rows = slice(base[l], base[l] + 2 * l + 1)
                    matrix = output_maps[min(l, l_max)]
                    mats[rows] = np.einsum("ik,tk...->ti...", matrix, mats[rows])
            return _Parity(l_first, l_last, mats, base)

        (_, even_last), (_, odd_last) = _parity_ranges(l_max)
        return pack(0, even_last, sums[0], (3, 3)), pack(1, odd_last, sums[1], (3, 3, 3))

    def _set_radial(self, radial: RadialProfile) -> None:
        self._radial = radial
        self._even_tables = _evaluation_tables(radial.table("R", self._even.degrees))
        self._odd_tables = _evaluation_tables(radial.table("dR", self._odd.degrees))

    def with_radial(self, radial: RadialProfile) -> GreenKernel:
        """A kernel for the same material with another falloff or radius (no quadrature)."""
        if not isinstance(radial, RadialProfile):
            raise ValueError(f"radial must be a RadialProfile (got {type(radial).__name__})")
        clone = object.__new__(GreenKernel)
        clone.__dict__.update(self.__dict__)
        clone._set_radial(radial)
        return clone

    def with_eps(self, eps: float) -> GreenKernel:
        """The same kernel with regularization radius ``eps`` (falloff shape unchanged)."""
        return self.with_radial(self._radial.with_eps(eps))

    def with_degree_weights(
        self, degree_weights: Sequence[float], output_maps: np.ndarray | None = None
    ) -> GreenKernel:
        """The same kernel with other ``degree_weights`` (see the class docstring): no new
        quadrature, bit for bit ``GreenKernel(material, l_max, radial, degree_weights)``.

        output_maps : (l_max + 1, 3, 3), optional
            A linear map applied to the displacement of each degree l (of G, and l_max's for
            ∇G's top degree l_max + 1): u = Σ_l A_l u_l. The wrinkle brush keeps only the
            normal component of its high degrees this way (A_l = n nᵀ)."""
        weights = _checked_weights(degree_weights, self._l_max)
        if output_maps is not None:
            output_maps = np.asarray(output_maps, dtype=np.float64)
            if output_maps.shape != (self._l_max + 1, 3, 3) or not np.isfinite(output_maps).all():
                raise ValueError(
                    f"output_maps must be {self._l_max + 1} finite 3×3 matrices "
                    f"(got shape {output_maps.shape})"
                )
        clone = object.__new__(GreenKernel)
        clone.__dict__.update(self.__dict__)
        clone._weights = weights
        clone._even, clone._odd = self._pack(self._sums, self._l_max, weights, output_maps)
        return clone

    def degree_norms(self) -> np.ndarray:
        """(l_max + 2,) the size of each degree's material term, unweighted: the Frobenius norm
        of Σ_m P_lm (even l, G) or 𝒫_lm (odd l, ∇G), in the quadrature's units (compare them
        with each other). Zero for a degree the material does not have (l > 2 of an
        isotropic material, up to rounding)."""
        norms = np.zeros(self._l_max + 2)
        for parity, sums in zip((0, 1), self._sums, strict=True):
            first = parity
            offset = 0
            for l in range(first, self._l_max + 2, 2):
                if l > self._l_max + parity:
                    break
                rows = sums[offset : offset + 2 * l + 1]
                norms[l] = float(np.sqrt(np.sum(rows * rows)))
                offset += 2 * l + 1
        return norms

    # -- properties --------------------------------------------------------------------------
    @property
    def material(self) -> Material:
        return self._material

    @property
    def l_max(self) -> int:
        return self._l_max

    @property
    def radial(self) -> RadialProfile:
        return self._radial

    @property
    def eps(self) -> float:
        """Regularization radius ε of the falloff (model units)."""
        return self._radial.eps

    @property
    def degree_weights(self) -> np.ndarray:
        return self._weights

    # -- evaluation --------------------------------------------------------------------------
    def _run(
        self,
        parity: _Parity,
        tables: np.ndarray,
        points: np.ndarray,
        center: np.ndarray,
        coeffs: np.ndarray,
    ) -> np.ndarray:
        out = np.empty((points.shape[0], coeffs.shape[1]))
        if points.shape[0] == 0:
            return out
        qmm, rec_a, rec_b = self._recurrence
        coeffs = np.ascontiguousarray(coeffs, dtype=np.float64)
        expand(
            points,
            np.ascontiguousarray(center, dtype=np.float64),
            self._radial.eps,
            1 if parity.l_first == 0 else 2,
            parity.l_first,
            parity.l_last,
            parity.base,
            coeffs,
            tables,
            qmm,
            rec_a,
            rec_b,
            *parity.angular(coeffs.shape[1]),
            out,
        )
        return out

    def green(self, offsets: np.ndarray) -> np.ndarray:
        """G(x) at offsets x (N, 3) → (N, 3, 3), symmetric (units: 1/(stiffness·length)).

        Offsets beyond :data:`COORDINATE_LIMIT` raise ParameterError; within it G is finite."""
        pts = _points("offsets", offsets)
        coeffs = self._even.matrices.reshape(-1, 9)
        return self._run(self._even, self._even_tables, pts, np.zeros(3), coeffs).reshape(-1, 3, 3)

    def green_gradient(self, offsets: np.ndarray) -> np.ndarray:
        """∇G at offsets (N, 3) → (N, 3, 3, 3) with ``[n, i, j, p] = ∂G_ij/∂x_p``."""
        pts = _points("offsets", offsets)
        coeffs = self._odd.matrices.reshape(-1, 27)
        out = self._run(self._odd, self._odd_tables, pts, np.zeros(3), coeffs)
        return out.reshape(-1, 3, 3, 3)

    def displacement(self, points: np.ndarray, center: np.ndarray, force: np.ndarray) -> np.ndarray:
        """Vector load: u = G(points - center) · force → (N, 3).

        Finite for every point and center with coordinates within :data:`COORDINATE_LIMIT`
        (far away u decays as 1/r); beyond it, or for a force so large that u overflows, a
        :class:`~gogreen_core.validation.ParameterError` names the input.
        """
        pts = _points("points", points)
        c = _within_limit("center", _finite_array("center", center, (3,)))
        f = _finite_array("force", force, (3,))
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below
            coeffs = _load_coefficients("force", self._even.matrices @ f)  # (n_terms, 3)
        return self._run(self._even, self._even_tables, pts, c, coeffs)

    def affine_displacement(
        self, points: np.ndarray, center: np.ndarray, load: np.ndarray
    ) -> np.ndarray:
        """Affine load H (3, 3): u_i = Σ_jp ∂_p G_ij(points - center) H_jp → (N, 3).

        Finite within :data:`COORDINATE_LIMIT` as :meth:`displacement` (decay 1/r²)."""
        pts = _points("points", points)
        c = _within_limit("center", _finite_array("center", center, (3,)))
        h = _finite_array("affine load", load, (3, 3))
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below
            coeffs = np.einsum("tijp,jp->ti", self._odd.matrices, h)
        coeffs = _load_coefficients("affine load", coeffs)
        return self._run(self._odd, self._odd_tables, pts, c, coeffs)

    def streamlines(
        self,
        points: np.ndarray,
        center: np.ndarray,
        load: np.ndarray,
        *,
        center_step: np.ndarray | None = None,
        cutoff: tuple[float, float] | None = None,
        mirror_signs: np.ndarray | None = None,
        origin: np.ndarray | None = None,
        substeps: int = 4,
        tolerance: float | None = STREAMLINE_TOLERANCE,
        indices: np.ndarray | None = None,
        in_place: bool = False,
    ) -> np.ndarray:
        """Move ``points`` (N, 3) along the load's displacement field taken as a velocity.

        Integrates dx/dt = v(x, t) over pseudo-time t ∈ [0, 1] by RK4 (paper Sec. 3.2) and
        returns the end positions (N, 3).

        v(x, t) = Σ_M M s(|y - c(t)|) u(y - c(t)) with y = origin + M (x - origin):

        * ``load``: a force (3,) (u = G f) or an affine load (3, 3) (u_i = ∂_p G_ij H_jp);
        * c(t) = center + t · center_step: a moving load (a grab following the cursor);
        * s: C² cutoff (quintic smoothstep) equal to 1 up to ``cutoff[0]`` and 0 from
          ``cutoff[1]`` on (model units); None for no cutoff;
        * M: diagonal reflections given by ``mirror_signs`` (n_m, 3) of ±1, the first row
          being (1, 1, 1); None for the brush alone.

        Step control:

        * ``tolerance`` (default :data:`STREAMLINE_TOLERANCE`, 1e-4): adaptive. Every point
          takes one RK4 step; an error estimate per point (the midpoint rule that shares RK4's
          first two stages, see ``_expansion.stream``) sends the points whose predicted error
          exceeds a safe fraction of ``tolerance`` times the motion scale (the largest of
          |center_step| and every point's motion) back for 2, 4, ... up to 256 RK4 steps. The
          target: every point within ``tolerance`` · scale of the fixed 64-step result.
          ``substeps`` is then not used (a Brush's ``substeps`` no longer matters for
          grab events through the Sculptor).
        * ``tolerance=None``: ``substeps`` fixed RK4 steps for every point (the reference).

        Both are deterministic: the same input gives bit-identical output whatever the number
        of threads (points are processed in fixed blocks), so undo and replay are exact.

        Rows of a larger array, without copies (a mesh being sculpted):

        * ``indices`` (n,) int: move only the rows ``points[indices]``, read in place; the
          result (n, 3) is bit for bit that of ``streamlines(points[indices], ...)``.
        * ``in_place``: also write the end positions into ``points`` (a C-contiguous float64
          (N, 3) array) at ``indices`` (every row if None), and only if all of them are
          finite: otherwise ValueError and ``points`` is unchanged.
        """
        return self._streamlines(
            points,
            center,
            load,
            center_step=center_step,
            cutoff=cutoff,
            mirror_signs=mirror_signs,
            origin=origin,
            substeps=substeps,
            tolerance=tolerance,
            indices=indices,
            in_place=in_place,
        )[0]

    def _streamlines(
        self,
        points: np.ndarray,
        center: np.ndarray,
        load: np.ndarray,
        *,
        center_step: np.ndarray | None = None,
        cutoff: tuple[float, float] | None = None,
        mirror_signs: np.ndarray | None = None,
        origin: np.ndarray | None = None,
        substeps: int = 4,
        tolerance: float | None = STREAMLINE_TOLERANCE,
        indices: np.ndarray | None = None,
        in_place: bool = False,
        out: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`streamlines`, also returning the RK4 steps each point took (N,) int64 (for
        benchmarks and tests: 4 velocity evaluations per step). ``out``: a C-contiguous
        float64 array of at least n rows whose first n rows receive the result (a buffer the
        caller reuses between events; the result is a view of it)."""
        if in_place:
            if not (
                isinstance(points, np.ndarray)
                and points.dtype == np.float64
                and points.ndim == 2
                and points.shape[1] == 3
                and points.flags.c_contiguous
                and points.flags.writeable
            ):
                raise ParameterError(
                    "points",
                    "in_place needs points as a writable C-contiguous (N, 3) float64 array",
                )
        if indices is None:
            pts = _points("points", points)  # the array itself if in_place (checked above)
            rows = np.zeros(0, dtype=np.int64)
        else:
            rows = np.asarray(indices)
            if rows.ndim != 1 or not (rows.size == 0 or np.issubdtype(rows.dtype, np.integer)):
                raise ParameterError("indices", f"indices must be 1-D integers (got {rows.dtype})")
            rows = np.ascontiguousarray(rows, dtype=np.int64)
            pts = np.asarray(points, dtype=np.float64)
            if pts.ndim != 2 or pts.shape[1] != 3:
                raise ParameterError("points", f"points must have shape (N, 3) (got {pts.shape})")
            pts = np.ascontiguousarray(pts)
        c = _finite_array("center", center, (3,))
        step = (
            np.zeros(3) if center_step is None else _finite_array("center_step", center_step, (3,))
        )
        load = np.asarray(load, dtype=np.float64)
        if load.shape == (3,):
            parity, tables = self._even, self._even_tables
            coeffs = self._even.matrices @ _finite_array("force", load, (3,))
        elif load.shape == (3, 3):
            parity, tables = self._odd, self._odd_tables
            h = _finite_array("affine load", load, (3, 3))
            coeffs = np.einsum("tijp,jp->ti", self._odd.matrices, h)
        else:
            raise ValueError(
                f"load must be a force (3,) or an affine load (3, 3), got {load.shape}"
            )
        inner, outer = (0.0, 0.0) if cutoff is None else (float(cutoff[0]), float(cutoff[1]))
        if cutoff is not None and not (np.isfinite(outer) and 0.0 <= inner < outer):
            raise ValueError(f"cutoff must satisfy 0 <= inner < outer, finite (got {cutoff})")
        signs = np.ones((1, 3)) if mirror_signs is None else np.asarray(mirror_signs, float)
        if signs.ndim != 2 or signs.shape[1] != 3 or not np.all(np.abs(signs) == 1):
            raise ValueError("mirror_signs must be an (n, 3) array of +1/-1")
        if not np.all(signs[0] == 1):
            raise ValueError("the first row of mirror_signs must be (1, 1, 1), the brush itself")
        o = np.zeros(3) if origin is None else _finite_array("origin", origin, (3,))
        if (
            isinstance(substeps, bool)
            or not isinstance(substeps, (int, np.integer))
            or substeps < 1
        ):
            raise ValueError(f"substeps must be an integer >= 1 (got {substeps!r})")
        if tolerance is None:
            tol = 0.0
        else:
            tol = check_number("tolerance", tolerance, low=0.0, low_open=True)
        n = pts.shape[0] if indices is None else rows.shape[0]
        if out is None:
            result = np.empty((n, 3))
        else:
            if not (out.dtype == np.float64 and out.ndim == 2 and out.shape[1] == 3):
                raise ValueError(f"out must be a float64 (n, 3) array (got {out.shape})")
            result = out[:n]
            if len(result) < n or not result.flags.c_contiguous:
                raise ValueError(f"out must be C-contiguous with at least {n} rows")
        steps = np.empty(n, dtype=np.int64)
        if n == 0:
            return result, steps
        qmm, rec_a, rec_b = self._recurrence
        status = stream(
            pts,
            rows,
            indices is not None,
            in_place,
            COORDINATE_LIMIT,
            c,
            step,
            self._radial.eps,
            1 if parity.l_first == 0 else 2,
            parity.l_first,
            parity.l_last,
            parity.base,
            np.ascontiguousarray(coeffs),
            tables,
            qmm,
            rec_a,
            rec_b,
            *parity.angular(3),
            inner,
            outer,
            np.ascontiguousarray(signs),
            o,
            int(substeps),
            tol,
            result,
            steps,
        )
        if status == 1:
            raise ParameterError("indices", f"indices must be rows 0 to {len(pts) - 1}")
        if status == 2:
            raise ParameterError(
                "points",
                "points contain non-finite values (NaN or inf) or coordinates beyond the "
                f"supported {COORDINATE_LIMIT:g} in the rows of indices",
            )
        if status == 3:
            raise StreamlineOverflow(
                "the streamlines would move points to infinity; nothing was moved"
            )
        return result, steps

    def warm_up(self) -> float:
        """Compile, or load from numba's disk cache, everything this kernel's truncation degree
        evaluates with (vector and affine loads, streamlines); returns the seconds it took.

        Kernels of a new l_max (shipped as generated source) are compiled on first use, a few
        seconds once per machine (see also :func:`prepare_degree`, which the app runs in the
        background).
        """
        start = time.perf_counter()
        points = np.zeros((2, 3))
        points[1] = 1.0
        origin = np.zeros(3)
        for load in (np.ones(3), np.eye(3)):
            self.streamlines(points, origin, load, cutoff=(1.0, 2.0), substeps=1)
        self.displacement(points, origin, np.ones(3))
        self.affine_displacement(points, origin, np.eye(3))
        return time.perf_counter() - start

    def __repr__(self) -> str:
        return f"GreenKernel(l_max={self._l_max}, radial={self._radial!r})"
