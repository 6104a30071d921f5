"""The regularized Green's function of any linear elastic material (Chen & Desbrun 2022).

G(x) = 1/(2π²) Σ_{l even} i^l R_l(r) Σ_m Y_lm(x̂) P_lm              (paper Eq. 10)
∂_p G(x) = 1/(2π²) Σ_{l odd} i^{l+1} ℛ_l(r) Σ_m Y_lm(x̂) 𝒫_lm,p     (paper Eq. 12)

with M(ξ)_ik = C_ijkl ξ_j ξ_l, P_lm = ∫_S² M(ξ̂)⁻¹ Y_lm(ξ̂) dS and 𝒫_lm,p = ∫_S² M⁻¹ Y_lm ξ̂_p dS in
the real SH basis of ``sph.py`` (exact by the addition theorem, so everything stays real). The
material matrices are integrated once (:func:`material_rule`); R_l and ℛ_l come from the radial
profile's tables; evaluation is the numba code behind ``_evaluation.py``. G is truncated at even
l ≤ l_max and ∇G at odd l ≤ l_max + 1. The quadrature sums (:func:`_material_sums`) are the
expensive part; packing them with signs, 1/(2π²), degree weights and output maps
(:func:`_pack_terms`) takes microseconds, so a kernel repacks for other weights.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from gogreen_core import _compiled
from gogreen_core.field import _drivers, _evaluation, _stream
from gogreen_core.field._evaluation import Parity
from gogreen_core.field._expansion import SEGMENT_DEGREE
from gogreen_core.physics.material import Material
from gogreen_core.physics.quadrature import lebedev_points, material_rule
from gogreen_core.physics.radial import TABLE_DEGREE, GaussianRadial, RadialProfile
from gogreen_core.physics.radial_tables import single_tables
from gogreen_core.physics.sph import real_sph_harm
from gogreen_core.physics.sph_rotation import real_wigner_d
from gogreen_core.validation import ParameterError, check_finite, check_integer, check_number

__all__ = [
    "COORDINATE_LIMIT",
    "L_MAX_LIMIT",
    "GreenKernel",
    "StreamlineOverflow",
    "lebedev_points",
    "prepare_degree",
]

#: Highest supported truncation degree.
L_MAX_LIMIT = 60


class StreamlineOverflow(ValueError):
    """The streamlines would move a point to infinity (nothing was moved)."""


#: Default error target of :meth:`GreenKernel.streamlines`, relative to the motion scale.
STREAMLINE_TOLERANCE = 1e-4


def prepare_degree(l_max: int) -> float:
    """Bring in the compiled code of truncation degree ``l_max`` and wait for it (evaluations
    never do: they run in NumPy until then); returns the seconds it took. Thread safe."""
    return _compiled.prepare(*_drivers.units_for(l_max))


#: Largest coordinate magnitude of points, offsets and centers: differences and norms of such
#: values stay finite, so every point within it gets a finite value (beyond: ParameterError).
COORDINATE_LIMIT = 1e300


def _finite_array(name: str, value: ArrayLike, shape: tuple[int, ...]) -> np.ndarray:
    return np.array(check_finite(name, value, shape))  # a writable copy: one compiled type


def _within_limit(name: str, arr: np.ndarray) -> np.ndarray:
    if arr.size and np.abs(arr).max() > COORDINATE_LIMIT:
        raise ParameterError(
            name,
            f"{name} has a coordinate of magnitude {np.abs(arr).max():.3g}, beyond the "
            f"supported {COORDINATE_LIMIT:g}",
        )
    return arr


def _points(name: str, value: ArrayLike) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ParameterError(name, f"{name} must have shape (N, 3) (got {arr.shape})")
    if not np.isfinite(arr).all():
        raise ParameterError(name, f"{name} contain non-finite values (NaN or inf)")
    return _writable(_within_limit(name, arr))


def _load_name(shape: tuple[int, ...]) -> str:
    return "force" if shape == (3,) else "affine load"


def _writable(arr: np.ndarray) -> np.ndarray:
    """``arr`` C-contiguous and writable (a copy if it is not): the compiled functions are
    typed for such arrays, and a read-only one would compile them again."""
    arr = np.ascontiguousarray(arr)
    return arr if arr.flags.writeable else arr.copy()


def _parity_ranges(l_max: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(first, last) degree of each parity for truncation ``l_max``: even l ≤ l_max for G,
    odd l ≤ l_max + 1 for ∇G."""
    return (0, l_max - l_max % 2), (1, l_max + 1 - l_max % 2)


def _checked_weights(degree_weights: Sequence[float] | np.ndarray | None, l_max: int) -> np.ndarray:
    """Degree weights (l_max + 1,), read-only: all ones for None; ValueError for the wrong
    count or a value that is not finite."""
    weights = np.ones(l_max + 1) if degree_weights is None else np.array(degree_weights, float)
    if weights.shape != (l_max + 1,):
        count = f"l_max + 1 = {l_max + 1}"
        raise ValueError(f"degree_weights must have {count} values (got shape {weights.shape})")
    check_finite("degree_weights", weights)
    weights.setflags(write=False)
    return weights


def _material_sums(material: Material, l_max: int) -> tuple[np.ndarray, np.ndarray]:
    """Σ_q w_q Y_lm(ξ_q) M⁻¹(ξ_q) for even l ≤ l_max ((n_even, 9)) and Σ_q w_q Y_lm(ξ_q)
    M⁻¹(ξ_q) ξ_q,p for odd l ≤ l_max + 1 ((n_odd, 27)): paper Eq. 10 and 12 before signs,
    normalization and weights."""
    nodes, qw = material_rule(material, l_max)
    (_, even_last), (_, odd_last) = _parity_ranges(l_max)
    even_rows = [c for l in range(0, even_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
    odd_rows = [c for l in range(1, odd_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
    # in chunks of nodes that bound the harmonics to ~64 MB
    even_sum: np.ndarray | float = 0.0
    odd_sum: np.ndarray | float = 0.0
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
    return np.asarray(even_sum), np.asarray(odd_sum)


def _pack_terms(
    sums: tuple[np.ndarray, np.ndarray],
    l_max: int,
    weights: np.ndarray,
    output_maps: np.ndarray | None = None,
) -> tuple[Parity, Parity]:
    """The even and odd packed coefficients: the sums times i^l (even l) or i^(l+1) (odd l),
    both real, the 1/(2π²) and the degree weight (the odd degree l takes ``weights[l − 1]``),
    then each degree's output map (``output_maps[l]``, l_max's for ∇G's top degree)."""
    if output_maps is not None:
        output_maps = check_finite("output_maps", output_maps, (l_max + 1, 3, 3))

    def pack(l_first: int, l_last: int, sums: np.ndarray, shape: tuple[int, ...]) -> Parity:
        base = np.full(l_last + 1 if l_last >= 0 else 1, -1, dtype=np.int64)
        factors: list[float] = []
        offset = 0
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
                mats[rows] = np.einsum("ik,tk...->ti...", output_maps[min(l, l_max)], mats[rows])
        return Parity(l_first, l_last, mats, base)

    (_, even_last), (_, odd_last) = _parity_ranges(l_max)
    return pack(0, even_last, sums[0], (3, 3)), pack(1, odd_last, sums[1], (3, 3, 3))


# _expansion unrolls the segment polynomial for this degree
assert TABLE_DEGREE == SEGMENT_DEGREE


class GreenKernel:
    """Regularized Green's function G and its gradient for one ``material`` and falloff
    ``radial`` (default ``GaussianRadial(1.0)``; it sets ε), truncated at ``l_max`` (0 to 60).
    ``degree_weights`` (l_max + 1,), default ones, scale G's degree-l term and ∇G's degree
    l + 1 term (the wrinkle brush). :meth:`with_radial`, :meth:`with_degree_weights` and
    :meth:`turned` reuse the quadrature.
    """

    def __init__(
        self,
        material: Material,
        l_max: int = 8,
        radial: RadialProfile | None = None,
        degree_weights: Sequence[float] | np.ndarray | None = None,
    ):
        if not isinstance(material, Material):
            message = f"material must be a Material (got {type(material).__name__})"
            raise ParameterError("material", message)
        l_max = check_integer("l_max", l_max, low=0, high=L_MAX_LIMIT)
        self._material, self._l_max = material, l_max
        self._weights = _checked_weights(degree_weights, l_max)
        self._sums = _material_sums(material, l_max)
        self._even, self._odd = _pack_terms(self._sums, l_max, self._weights)
        self._set_radial(GaussianRadial(1.0) if radial is None else radial)

    def _set_radial(self, radial: RadialProfile) -> None:
        if not isinstance(radial, RadialProfile):
            raise ValueError(f"radial must be a RadialProfile (got {type(radial).__name__})")
        self._radial = radial
        # (n_degrees, S, D+1), C-contiguous: the layout ``_expansion._radial`` reads
        self._even_tables = np.ascontiguousarray(radial.table("R", self._even.degrees))
        self._odd_tables = np.ascontiguousarray(radial.table("dR", self._odd.degrees))
        # the streamlines' single precision degrees: those above each parity's lowest
        self._even_single = single_tables(radial, "R", self._even.degrees[1:])
        self._odd_single = single_tables(radial, "dR", self._odd.degrees[1:])

    def with_radial(self, radial: RadialProfile) -> GreenKernel:
        """A kernel for the same material with another falloff or radius (no quadrature)."""
        clone = copy.copy(self)
        clone._set_radial(radial)
        return clone

    def with_eps(self, eps: float) -> GreenKernel:
        """The same kernel with regularization radius ``eps`` (falloff shape unchanged)."""
        return self.with_radial(self._radial.with_eps(eps))

    def with_degree_weights(
        self, degree_weights: Sequence[float] | np.ndarray, output_maps: np.ndarray | None = None
    ) -> GreenKernel:
        """The same kernel with other ``degree_weights``, bit for bit a new one built with them.
        ``output_maps`` (l_max + 1, 3, 3), optional: a linear map A_l applied to each degree's
        displacement, u = Σ_l A_l u_l (:func:`_pack_terms`)."""
        weights = _checked_weights(degree_weights, self._l_max)
        clone = copy.copy(self)
        clone._weights = weights
        clone._even, clone._odd = _pack_terms(self._sums, self._l_max, weights, output_maps)
        return clone

    def turned(self, rotation: np.ndarray) -> GreenKernel:
        """The kernel of the material turned by the proper rotation ``rotation`` F (3, 3):
        G'(x) = F G(Fᵀx) Fᵀ, exact, from this kernel's quadrature sums in a fraction of a
        millisecond (a new quadrature: tens to hundreds; ``benchmarks/material_frame.py``). For
        C' = F·C, M'(ξ) = F M(Fᵀξ) Fᵀ, so with Y_l(F η) = D_l(F) Y_l(η) (``real_wigner_d``), the
        material terms of paper Eq. 10 and 12 turn as

            P'_lm = F [Σ_m' D_l(F)_mm' P_lm'] Fᵀ                          (G's terms, even l)
            𝒫'_lm,ijp = Σ_m' D_l(F)_mm' F_ia F_jb F_pc 𝒫_lm',abc        (∇G's terms, odd l)
        """
        material = self._material.rotated(rotation)  # checks the rotation
        f = np.asarray(rotation, dtype=np.float64)
        (_, even_last), (_, odd_last) = _parity_ranges(self._l_max)
        wigner = real_wigner_d(f, max(even_last, odd_last, 0))
        even, odd = self._sums
        out_even, out_odd = np.empty_like(even), np.empty_like(odd)
        for l in range(0, even_last + 1, 2):
            rows = slice(l * (l - 1) // 2, (l + 1) * (l + 2) // 2)  # the 2l + 1 rows of degree l
            mixed = (wigner[l] @ even[rows]).reshape(-1, 3, 3)
            out_even[rows] = np.einsum("ia,tab,jb->tij", f, mixed, f).reshape(-1, 9)
        for l in range(1, odd_last + 1, 2):
            rows = slice(l * (l - 1) // 2, (l + 1) * (l + 2) // 2)
            mixed = (wigner[l] @ odd[rows]).reshape(-1, 3, 3, 3)
            out_odd[rows] = np.einsum("ia,jb,pc,tabc->tijp", f, f, f, mixed).reshape(-1, 27)
        clone = copy.copy(self)
        clone._material, clone._sums = material, (out_even, out_odd)
        clone._even, clone._odd = _pack_terms(clone._sums, self._l_max, self._weights)
        return clone

    def degree_norms(self) -> np.ndarray:
        """(l_max + 2,) the Frobenius norm of each degree's quadrature sums, unweighted (Σ_m P_lm
        for even l, 𝒫_lm for odd l), comparable between degrees of one parity."""
        norms = np.zeros(self._l_max + 2)
        for (first, last), parity_sums in zip(_parity_ranges(self._l_max), self._sums, strict=True):
            for l in range(first, last + 1, 2):
                rows = parity_sums[l * (l - 1) // 2 : (l + 1) * (l + 2) // 2]
                norms[l] = float(np.sqrt(np.sum(rows * rows)))
        return norms

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

    def _run(
        self, parity: Parity, pts: np.ndarray, c: np.ndarray, coeffs: np.ndarray
    ) -> np.ndarray:
        tables = self._even_tables if parity is self._even else self._odd_tables
        return _evaluation.expand(parity, tables, self._radial.eps, pts, c, coeffs)

    def green(self, offsets: np.ndarray) -> np.ndarray:
        """G(x) at offsets x (N, 3) → (N, 3, 3), symmetric (units: 1/(stiffness·length)),
        finite within :data:`COORDINATE_LIMIT` (beyond: ParameterError)."""
        pts = _points("offsets", offsets)
        coeffs = self._even.matrices.reshape(-1, 9)
        return self._run(self._even, pts, np.zeros(3), coeffs).reshape(-1, 3, 3)

    def green_gradient(self, offsets: np.ndarray) -> np.ndarray:
        """∇G at offsets (N, 3) → (N, 3, 3, 3) with ``[n, i, j, p] = ∂G_ij/∂x_p``."""
        pts = _points("offsets", offsets)
        coeffs = self._odd.matrices.reshape(-1, 27)
        return self._run(self._odd, pts, np.zeros(3), coeffs).reshape(-1, 3, 3, 3)

    def displacement(self, points: np.ndarray, center: np.ndarray, force: np.ndarray) -> np.ndarray:
        """Vector load: u = G(points - center) · force → (N, 3). Finite within
        :data:`COORDINATE_LIMIT` (decay 1/r); beyond it, or for a force so large that u
        overflows, a :class:`~gogreen_core.validation.ParameterError` names the input."""
        return self._displace(points, center, force, (3,))

    def affine_displacement(
        self, points: np.ndarray, center: np.ndarray, load: np.ndarray
    ) -> np.ndarray:
        """Affine load H (3, 3): u_i = Σ_jp ∂_p G_ij(points - center) H_jp → (N, 3); finite
        within :data:`COORDINATE_LIMIT` as :meth:`displacement` (decay 1/r²)."""
        return self._displace(points, center, load, (3, 3))

    def _displace(
        self, points: np.ndarray, center: np.ndarray, load: ArrayLike, shape: tuple[int, ...]
    ) -> np.ndarray:
        pts = _points("points", points)
        c = _within_limit("center", _finite_array("center", center, (3,)))
        parity, _, _, coeffs = self._loaded(load, shape)
        if not np.isfinite(coeffs).all():
            name = _load_name(shape)
            raise ParameterError(
                name, f"{name} is too large for this material: its expansion overflows"
            )
        return self._run(parity, pts, c, coeffs)

    def _loaded(
        self, load: ArrayLike, shape: tuple[int, ...]
    ) -> tuple[Parity, np.ndarray, np.ndarray, np.ndarray]:
        """The parity of a force (3,) or an affine load (3, 3), its radial tables (double and
        single precision) and the load's coefficients (n_terms, 3)."""
        value = _finite_array(_load_name(shape), load, shape)
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported by callers
            if shape == (3,):
                return self._even, self._even_tables, self._even_single, self._even.matrices @ value
            coeffs = np.einsum("tijp,jp->ti", self._odd.matrices, value)
        return self._odd, self._odd_tables, self._odd_single, coeffs

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
        rows_checked: bool = False,
        out: np.ndarray | None = None,
        evaluations: np.ndarray | None = None,
    ) -> np.ndarray:
        """The end positions (N, 3) of ``points`` (N, 3) moved along the load's displacement
        taken as a velocity, dx/dt = v(x, t) over pseudo-time t ∈ [0, 1] by RK4 (paper
        Sec. 3.2): v(x, t) = Σ_M M s(|y - c(t)|) u(y - c(t)) with y = origin + M (x - origin),
        u of the ``load`` (a force (3,) or an affine load (3, 3)), c(t) = center + t ·
        center_step, s the C² ``cutoff`` (1 up to its first radius, 0 from its second; None:
        none), M the reflections of ``mirror_signs`` (n_m, 3) of ±1 (first row (1, 1, 1)).

        ``tolerance``: adaptive steps, every point within ``tolerance`` times the motion scale
        (the largest of |center_step| and every point's motion) of the fixed 64-step result;
        None: ``substeps`` fixed RK4 steps. Bit-identical whatever the number of threads.
        ``indices`` (n,) int: move only ``points[indices]``, read in place. ``in_place``: also
        write the ends into ``points`` (writable C-contiguous float64) at ``indices`` if all are
        finite (else ValueError, ``points`` unchanged). ``rows_checked`` (distinct rows, finite
        within :data:`COORDINATE_LIMIT`): the ends go there as made, not into the result.
        ``out``: a reused C-contiguous float64 buffer of at least n rows, the result a view of it.
        ``evaluations``: int64 (n,), gets the velocity evaluations each point took (4 a step).
        """
        if in_place and _writable(np.asarray(points, dtype=np.float64)) is not points:
            message = "in_place needs points as a writable C-contiguous (N, 3) float64 array"
            raise ParameterError("points", message)
        if indices is None:
            pts = _points("points", points)  # the array itself if in_place (checked above)
            rows = np.zeros(0, dtype=np.int64)
        else:
            rows = np.asarray(indices)
            if rows.ndim != 1 or not (rows.size == 0 or np.issubdtype(rows.dtype, np.integer)):
                raise ParameterError("indices", f"indices must be 1-D integers (got {rows.dtype})")
            rows = _writable(rows.astype(np.int64, copy=False))
            pts = _writable(np.asarray(points, dtype=np.float64))
            if pts.ndim != 2 or pts.shape[1] != 3:
                raise ParameterError("points", f"points must have shape (N, 3) (got {pts.shape})")
        c = _finite_array("center", center, (3,))
        step = np.zeros(3) if center_step is None else center_step
        step = _finite_array("center_step", step, (3,))
        shape = np.shape(load)
        if shape not in ((3,), (3, 3)):
            raise ValueError(f"load must be a force (3,) or an affine load (3, 3), got {shape}")
        parity, tables, single, coeffs = self._loaded(load, shape)
        inner, outer = (0.0, 0.0) if cutoff is None else (float(cutoff[0]), float(cutoff[1]))
        if cutoff is not None and not (np.isfinite(outer) and 0.0 <= inner < outer):
            raise ValueError(f"cutoff must satisfy 0 <= inner < outer, finite (got {cutoff})")
        signs = np.ones((1, 3)) if mirror_signs is None else np.array(mirror_signs, float)
        if signs.ndim != 2 or signs.shape[1] != 3 or not np.all(np.abs(signs) == 1):
            raise ValueError("mirror_signs must be an (n, 3) array of +1/-1")
        if not np.all(signs[0] == 1):
            raise ValueError("the first row of mirror_signs must be (1, 1, 1), the brush itself")
        o = np.zeros(3) if origin is None else _finite_array("origin", origin, (3,))
        substeps = check_integer("substeps", substeps, low=1)
        tol = 0.0
        if tolerance is not None:
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
        if evaluations is None:
            evaluations = np.empty(0, dtype=np.int64)
        elif evaluations.dtype != np.int64 or evaluations.shape != (n,):
            raise ValueError(f"evaluations must be an int64 array of {n} counts")
        if n == 0:
            return result
        field, run_pass = _evaluation.stream_field(
            parity, tables, single, self._radial.eps, coeffs, c, step, (inner, outer), signs, o
        )
        status = _stream.stream(
            pts, rows, indices is not None, in_place, COORDINATE_LIMIT, field, substeps, tol,
            result, evaluations, run_pass, rows_checked,
        )  # fmt: skip
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
        return result

    def warm_up(self) -> float:
        """:func:`prepare_degree` of this kernel's l_max, then one evaluation of each kind;
        returns the seconds it took."""
        start = time.perf_counter()
        prepare_degree(self._l_max)
        points = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
        origin = np.zeros(3)
        for load in (np.ones(3), np.eye(3)):
            self.streamlines(points, origin, load, cutoff=(1.0, 2.0), substeps=1)
        self.displacement(points, origin, np.ones(3))
        self.affine_displacement(points, origin, np.eye(3))
        return time.perf_counter() - start

    def __repr__(self) -> str:
        return f"GreenKernel(l_max={self._l_max}, radial={self._radial!r})"
