"""The symmetry of a stiffness for display (Go Green's Fig. 12 colours equal coefficients of
the homogenized 6x6 stiffness alike): :func:`describe_symmetry` groups equal coefficients and
names the class *in the axes of the given Voigt matrix* (a rotated material reads as "other").

Conditions (Voigt order 11, 22, 33, 23, 13, 12), all within ``rtol * max|C|``:

- orthotropic: the normal/shear coupling block and the shear off-diagonals vanish;
- transversely isotropic about z: orthotropic, C11 = C22, C13 = C23, C44 = C55 and
  C66 = (C11 − C12) / 2 (likewise about x or y);
- tetragonal about z: the same without the C66 condition (square fibre arrays);
- cubic: orthotropic, C11 = C22 = C33, C12 = C13 = C23, C44 = C55 = C66;
- isotropic: cubic and C44 = (C11 − C12) / 2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gogreen_core.physics.material import Material
from gogreen_core.validation import check_finite, check_number

__all__ = ["SYMMETRY_CLASSES", "SymmetryDescription", "describe_symmetry"]

#: Class names, from most to least symmetric.
SYMMETRY_CLASSES = (
    "isotropic",
    "cubic",
    "transversely isotropic",
    "tetragonal",
    "orthotropic",
    "other",
)


@dataclass(frozen=True)
class SymmetryDescription:
    """Result of :func:`describe_symmetry`: ``groups`` (6, 6) int, equal coefficients share a
    label 0, 1, ... (row-major order of first appearance), zeros -1; ``symmetry_class`` one of
    :data:`SYMMETRY_CLASSES`; ``axis`` "x", "y" or "z" of a transversely isotropic or tetragonal
    class, else None; ``values`` (6, 6) the group mean of each coefficient (0 for zeros)."""

    groups: np.ndarray
    symmetry_class: str
    axis: str | None
    values: np.ndarray

    @property
    def group_count(self) -> int:
        """Number of distinct nonzero coefficient values."""
        return int(self.groups.max() + 1)


def _group_coefficients(c6: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    rows, cols = np.triu_indices(6)
    vals = c6[rows, cols]
    groups = np.full((6, 6), -1, dtype=np.int64)
    means = np.zeros((6, 6))
    # Cluster sorted nonzero values: consecutive values closer than tol join one group ...
    nonzero = np.flatnonzero(np.abs(vals) > tol)
    order = nonzero[np.argsort(vals[nonzero], kind="stable")]
    raw = np.full(len(vals), -1, dtype=np.int64)
    raw[order] = np.concatenate([[0], np.cumsum(np.diff(vals[order]) > tol)])
    # ... labelled in row-major order of first appearance.
    relabel: dict[int, int] = {}
    for r, c, lab in zip(rows, cols, raw, strict=True):
        if lab >= 0:
            groups[r, c] = groups[c, r] = relabel.setdefault(int(lab), len(relabel))
    for label in range(len(relabel)):
        mask = groups == label
        means[mask] = c6[mask].mean()
    return groups, means


def describe_symmetry(material: Material | np.ndarray, rtol: float = 1e-5) -> SymmetryDescription:
    """Equal-coefficient groups and symmetry class of a :class:`Material` or (6, 6) Voigt
    stiffness, in its own axes. Two coefficients are equal (a coefficient zero) when they differ
    by at most ``rtol * max|C|`` (the homogenizer is accurate to better than 1e-6)."""
    voigt = material.voigt if isinstance(material, Material) else material
    c6 = check_finite("voigt", voigt, (6, 6))
    rtol = check_number("rtol", rtol, low=0.0, high=1.0, high_open=True)
    c6 = 0.5 * (c6 + c6.T)
    tol = rtol * float(np.abs(c6).max())
    groups, means = _group_coefficients(c6, tol)

    def eq(a: float, b: float) -> bool:
        return abs(a - b) <= tol

    off = np.concatenate([c6[:3, 3:].ravel(), [c6[3, 4], c6[3, 5], c6[4, 5]]])
    orthotropic = bool(np.all(np.abs(off) <= tol))
    cls, axis = "other", None
    if orthotropic:
        cls = "orthotropic"
        d = np.diag(c6)
        c12, c13, c23 = c6[0, 1], c6[0, 2], c6[1, 2]
        pairs = ((d[0], d[1]), (d[1], d[2]), (c12, c13), (c13, c23), (d[3], d[4]), (d[4], d[5]))
        if all(eq(a, b) for a, b in pairs):  # cubic
            cls = "isotropic" if eq(d[3], 0.5 * (d[0] - c12)) else "cubic"
        else:
            # Axis z: 1 = 2 plane; axis x: 2 = 3 plane; axis y: 1 = 3 plane.
            candidates = (
                ("x", (1, 2), (0, 1), (0, 2), (5, 4), 3),
                ("y", (0, 2), (0, 1), (1, 2), (5, 3), 4),
                ("z", (0, 1), (0, 2), (1, 2), (4, 3), 5),
            )
            for name, (p, q), (a1, b1), (a2, b2), (s1, s2), s_plane in candidates:
                if eq(d[p], d[q]) and eq(c6[a1, b1], c6[a2, b2]) and eq(d[s1], d[s2]):
                    if eq(d[s_plane], 0.5 * (d[p] - c6[p, q])):
                        cls, axis = "transversely isotropic", name
                        break
                    if cls == "orthotropic":
                        cls, axis = "tetragonal", name
    groups.setflags(write=False)
    means.setflags(write=False)
    return SymmetryDescription(groups=groups, symmetry_class=cls, axis=axis, values=means)
