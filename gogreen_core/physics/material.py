"""Linear elastic materials: stiffness tensors in Voigt and full 4th-order form.

Voigt order is 11, 22, 33, 23, 13, 12 with engineering shear strains (gamma = 2 eps), so that
``voigt[a, b] = C[i, j, k, l]`` with (i, j) the index pair of ``a`` and (k, l) that of ``b``
(see ``../shared/MATH.md``). Stiffness units are whatever the caller uses (only ratios matter for
the displacement shapes; the Green's function scales as 1/stiffness).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, cast

import numpy as np

from gogreen_core.validation import check_finite, check_number

__all__ = ["VOIGT_PAIRS", "Material", "tensor_to_voigt", "uniaxial_stress", "voigt_to_tensor"]

#: Index pair (i, j) of each Voigt position, in the order 11, 22, 33, 23, 13, 12.
VOIGT_PAIRS: tuple[tuple[int, int], ...] = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
_ROWS, _COLS = np.array(VOIGT_PAIRS).T

# VOIGT_INDEX[i, j] -> Voigt position of the symmetric pair (i, j).
VOIGT_INDEX = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])

_SYMMETRY_RTOL = 1e-10


def voigt_to_tensor(voigt: np.ndarray) -> np.ndarray:
    """Expand a (6, 6) Voigt stiffness into the (3, 3, 3, 3) tensor C_ijkl."""
    voigt = np.asarray(voigt, dtype=np.float64)
    return cast(np.ndarray, voigt[VOIGT_INDEX[:, :, None, None], VOIGT_INDEX[None, None, :, :]])


def tensor_to_voigt(tensor: np.ndarray) -> np.ndarray:
    """Contract a (3, 3, 3, 3) stiffness tensor with minor symmetries into (6, 6) Voigt form."""
    tensor = np.asarray(tensor, dtype=np.float64)
    return cast(np.ndarray, tensor[_ROWS[:, None], _COLS[:, None], _ROWS[None, :], _COLS[None, :]])


def uniaxial_stress(directions: np.ndarray) -> np.ndarray:
    """The unit uniaxial stress d⊗d along unit ``directions`` (..., 3) in Voigt form (..., 6)."""
    return np.ascontiguousarray(directions[..., _ROWS] * directions[..., _COLS])


class Material:
    """A homogeneous linear elastic material, immutable, defined by its stiffness: build one
    with a named constructor (``isotropic``, ``from_lame``, ``cubic``, ``orthotropic``,
    ``transversely_isotropic``, ``from_voigt``)."""

    __slots__ = ("_tensor", "_voigt")

    def __init__(self, voigt: np.ndarray):
        c6 = np.asarray(voigt, dtype=np.float64)
        if c6.shape != (6, 6):
            raise ValueError(f"Voigt stiffness must be a 6x6 matrix (got shape {c6.shape})")
        if not np.all(np.isfinite(c6)):
            raise ValueError("Voigt stiffness must be finite")
        scale = np.abs(c6).max()
        if scale == 0:
            raise ValueError("Voigt stiffness is all zeros: not positive definite")
        asym = np.abs(c6 - c6.T).max()
        if asym > _SYMMETRY_RTOL * scale:
            raise ValueError(
                f"Voigt stiffness is not symmetric: max |C - C^T| = {asym:.3g} "
                f"(relative {asym / scale:.3g})"
            )
        c6 = 0.5 * c6 + 0.5 * c6.T  # halves first: entries near the float64 limit do not overflow
        eig = np.linalg.eigvalsh(c6)
        if eig[0] <= 1e-12 * eig[-1]:
            raise ValueError(
                f"Voigt stiffness is not positive definite: smallest eigenvalue {eig[0]:.6g} "
                f"(largest {eig[-1]:.6g})"
            )
        c6.setflags(write=False)
        tensor = voigt_to_tensor(c6)
        tensor.setflags(write=False)
        self._voigt = c6
        self._tensor = tensor

    # -- constructors -------------------------------------------------------------------------
    @classmethod
    def from_voigt(cls, voigt: np.ndarray) -> Material:
        """Any symmetric positive definite (6, 6) stiffness (21 independent coefficients)."""
        return cls(voigt)

    @classmethod
    def from_lame(cls, lam: float, mu: float) -> Material:
        """Isotropic material from the Lamé parameters λ and μ (admissible: μ > 0, 3λ + 2μ > 0)."""
        lam, mu = check_number("lam", lam), check_number("mu", mu)
        if mu <= 0:
            raise ValueError(f"shear modulus mu must be > 0 (got {mu})")
        if 3 * lam + 2 * mu <= 0:
            bulk3 = 3 * lam + 2 * mu
            raise ValueError(f"bulk modulus must be > 0: need 3*lam + 2*mu > 0 (got {bulk3})")
        return cls.cubic(lam + 2 * mu, lam, mu)

    @classmethod
    def isotropic(cls, young: float, poisson: float) -> Material:
        """Isotropic material from Young's modulus E > 0 and Poisson ratio -1 < ν < 1/2."""
        young, poisson = check_number("young", young), check_number("poisson", poisson)
        if young <= 0:
            raise ValueError(f"young (Young's modulus) must be > 0 (got {young})")
        if not -1.0 < poisson < 0.5:
            raise ValueError(f"poisson must lie in (-1, 1/2) (got {poisson})")
        lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
        mu = young / (2 * (1 + poisson))
        return cls.from_lame(lam, mu)

    @classmethod
    def cubic(cls, c11: float, c12: float, c44: float) -> Material:
        """Cubic material with axes x, y, z (admissible: c11 > |c12|, c11 + 2 c12 > 0, c44 > 0)."""
        c11, c12, c44 = check_number("c11", c11), check_number("c12", c12), check_number("c44", c44)
        c6 = np.zeros((6, 6))
        c6[:3, :3] = c12
        c6[[0, 1, 2], [0, 1, 2]] = c11
        c6[[3, 4, 5], [3, 4, 5]] = c44
        return cls(c6)

    @classmethod
    def orthotropic(
        cls,
        young: Sequence[float],
        shear: Sequence[float],
        poisson: Sequence[float],
    ) -> Material:
        """Orthotropic material with axes x, y, z: Young's moduli ``young`` (E1, E2, E3) and
        shear moduli ``shear`` (G23, G13, G12), all > 0, and ``poisson`` (ν12, ν13, ν23), with
        ν_ij = -ε_j / ε_i under uniaxial stress along i."""
        e = check_finite("young", young, (3,))
        g = check_finite("shear", shear, (3,))
        nu12, nu13, nu23 = check_finite("poisson", poisson, (3,))
        for name, val in zip(("E1", "E2", "E3", "G23", "G13", "G12"), (*e, *g), strict=True):
            if val <= 0:
                raise ValueError(f"modulus {name} must be > 0 (got {val})")
        e1, e2, e3 = e
        nu21, nu31, nu32 = nu12 * e2 / e1, nu13 * e3 / e1, nu23 * e3 / e2
        for name, nu, bound in (
            ("nu12", nu12, np.sqrt(e1 / e2)),
            ("nu13", nu13, np.sqrt(e1 / e3)),
            ("nu23", nu23, np.sqrt(e2 / e3)),
        ):
            if abs(nu) >= bound:
                a, b = name[2], name[3]
                raise ValueError(
                    f"inadmissible orthotropic Poisson ratio: need |{name}| < sqrt(E{a}/E{b}) = "
                    f"{bound:.6g} (got {nu})"
                )
        delta = 1 - nu12 * nu21 - nu23 * nu32 - nu13 * nu31 - 2 * nu21 * nu32 * nu13
        if delta <= 0:
            raise ValueError(
                "inadmissible orthotropic Poisson ratios: need "
                "1 - nu12*nu21 - nu23*nu32 - nu13*nu31 - 2*nu21*nu32*nu13 > 0 "
                f"(got {delta:.6g})"
            )
        s = np.zeros((6, 6))
        s[[0, 1, 2], [0, 1, 2]] = 1 / e
        s[[3, 4, 5], [3, 4, 5]] = 1 / g
        s[0, 1] = s[1, 0] = -nu12 / e1
        s[0, 2] = s[2, 0] = -nu13 / e1
        s[1, 2] = s[2, 1] = -nu23 / e2
        return cls(np.linalg.inv(s))

    @classmethod
    def transversely_isotropic(
        cls,
        young_plane: float,
        young_axial: float,
        poisson_plane: float,
        poisson_axial: float,
        shear_axial: float,
    ) -> Material:
        """Transversely isotropic material about z: Young's moduli E1 = E2 (``young_plane``)
        and E3 (``young_axial``), Poisson ratios ν12 (``poisson_plane``, |ν12| < 1) and
        ν13 = ν23 (``poisson_axial``), shear modulus G13 = G23 (``shear_axial``);
        G12 = E1 / (2 (1 + ν12))."""
        ep = check_number("young_plane", young_plane)
        nup = check_number("poisson_plane", poisson_plane)
        if not -1.0 < nup < 1.0:
            raise ValueError(f"poisson_plane must lie in (-1, 1) (got {nup})")
        g12 = ep / (2 * (1 + nup))
        return cls.orthotropic(
            young=(ep, ep, young_axial),
            shear=(shear_axial, shear_axial, g12),
            poisson=(nup, poisson_axial, poisson_axial),
        )

    # -- properties ---------------------------------------------------------------------------
    @property
    def voigt(self) -> np.ndarray:
        """(6, 6) read-only Voigt stiffness."""
        return self._voigt

    @property
    def tensor(self) -> np.ndarray:
        """(3, 3, 3, 3) read-only stiffness tensor C_ijkl."""
        return self._tensor

    @property
    def compliance(self) -> np.ndarray:
        """(6, 6) Voigt compliance S = C⁻¹ (engineering shear)."""
        return np.linalg.inv(self._voigt)

    def rotated(self, rotation: np.ndarray) -> Material:
        """The material turned by the rotation R (3, 3): C'_abcd = R_ai R_bj R_ck R_dl C_ijkl."""
        rot = check_finite("rotation", rotation, (3, 3))
        err = np.abs(rot @ rot.T - np.eye(3)).max()
        if err > 1e-9:
            raise ValueError(f"rotation is not orthonormal: max |R R^T - I| = {err:.3g}")
        if np.linalg.det(rot) < 0:
            raise ValueError("rotation has determinant -1: a reflection, not a proper rotation")
        c = np.einsum("ai,bj,ck,dl,ijkl->abcd", rot, rot, rot, rot, self._tensor, optimize=True)
        return Material(tensor_to_voigt(c))

    def acoustic_tensor(self, directions: np.ndarray) -> np.ndarray:
        """M(ξ)_ik = C_ijkl ξ_j ξ_l for directions (N, 3) → (N, 3, 3)."""
        d = np.asarray(directions, dtype=np.float64)
        return cast(np.ndarray, np.einsum("ijkl,nj,nl->nik", self._tensor, d, d, optimize=True))

    def directional_young(self, directions: np.ndarray) -> np.ndarray:
        """Young's modulus along unit directions (N, 3) → (N,): 1 / (d⊗d : S : d⊗d)."""
        d = np.asarray(directions, dtype=np.float64)
        # S maps the uniaxial stress σ to engineering strain: 1/E(d) = σ·(Sσ)
        sig = uniaxial_stress(d / np.linalg.norm(d, axis=1, keepdims=True))
        return cast(np.ndarray, 1.0 / np.einsum("na,ab,nb->n", sig, self.compliance, sig))

    # -- serialization ------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description: ``{"voigt": 6x6 nested list}``
        (:func:`gogreen_core.sculpt.schema.parse_material` reads it back)."""
        return {"voigt": self._voigt.tolist()}

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Material) and np.array_equal(self._voigt, other._voigt)

    def __hash__(self) -> int:
        return hash(self._voigt.tobytes())

    def __repr__(self) -> str:
        return f"Material(voigt=\n{np.array2string(self._voigt, precision=5)})"
