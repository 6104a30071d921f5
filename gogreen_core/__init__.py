"""GoGreen Sculpt numerics and sculpting engine (no GUI imports).

Regularized Green's functions of any linear elastic material by the spherical-harmonic expansion
of Chen & Desbrun, "Go Green: General Regularized Green's Functions for Elasticity" (2022).
"""

from gogreen_core.material import Material

__all__ = ["Material"]
