"""Independent references for the regularized Green's function (no spherical harmonics).

Plane-wave form: with s = x·ξ̂,  G(x) = (2π)⁻³ ∫_S² M(ξ̂)⁻¹ Φ(s) dS,  Φ(s) = ∫₀^∞ ĝ(k) cos(ks) dk
(ĝ even in k and M(-ξ̂) = M(ξ̂)), and ∂_p G = (2π)⁻³ ∫_S² M⁻¹ ξ̂_p Φ'(s) dS. For the Gaussian
load Φ(s) = (√π/ε) exp(-s²/ε²); for the Kelvinlet load Φ(s) = π·(3ε⁴/4)(s²+ε²)^(-5/2) (π times
the plane integral of g). The sphere is integrated in coordinates aligned with x̂: Gauss–Legendre
in u = cos θ (clustered where Φ varies, |u| ≲ ε/r) and the trapezoid rule in φ (spectral).
"""

from __future__ import annotations

import itertools

import numpy as np


def _phi(kind: str, s: np.ndarray, eps: float) -> tuple[np.ndarray, np.ndarray]:
    if kind == "gaussian":
        value = np.sqrt(np.pi) / eps * np.exp(-(s**2) / eps**2)
        return value, -2 * s / eps**2 * value
    base = s**2 + eps**2
    value = np.pi * 0.75 * eps**4 * base**-2.5
    return value, np.pi * 0.75 * eps**4 * (-5.0) * s * base**-3.5


def _sphere_rule(x: np.ndarray, eps: float, n_u: int = 240, n_phi: int = 160):
    r = np.linalg.norm(x)
    axis = x / r if r > 0 else np.array([0.0, 0.0, 1.0])
    helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    # u-panels: dense around u = 0 where exp(-r²u²/ε²) lives, coarser outside.
    width = min(1.0, 8 * eps / max(r, 1e-300))
    edges = np.unique(np.concatenate([np.linspace(-width, width, 9), [-1.0, 1.0]]))
    gx, gw = np.polynomial.legendre.leggauss(n_u // (len(edges) - 1) + 1)
    us, uw = [], []
    for lo, hi in itertools.pairwise(edges):
        us.append(0.5 * (hi - lo) * gx + 0.5 * (hi + lo))
        uw.append(0.5 * (hi - lo) * gw)
    u, wu = np.concatenate(us), np.concatenate(uw)
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    sin_t = np.sqrt(1 - u**2)
    dirs = (
        u[:, None, None] * axis
        + (sin_t[:, None] * np.cos(phi)[None, :])[:, :, None] * e1
        + (sin_t[:, None] * np.sin(phi)[None, :])[:, :, None] * e2
    ).reshape(-1, 3)
    weights = (wu[:, None] * np.full(n_phi, 2 * np.pi / n_phi)[None, :]).ravel()
    return dirs, weights, (r * u[:, None] * np.ones(n_phi)).ravel()


def reference_green(material, x, eps: float, kind: str = "gaussian"):
    """G (3, 3) and ∇G (3, 3, 3) with [i, j, p] = ∂G_ij/∂x_p at one offset x (3,)."""
    dirs, weights, s = _sphere_rule(np.asarray(x, dtype=float), eps)
    m_inv = np.linalg.inv(material.acoustic_tensor(dirs))
    value, slope = _phi(kind, s, eps)
    green = np.einsum("q,qij->ij", weights * value, m_inv) / (2 * np.pi) ** 3
    grad = np.einsum("q,qij,qp->ijp", weights * slope, m_inv, dirs) / (2 * np.pi) ** 3
    return green, grad


def kelvinlet_closed_form(x: np.ndarray, eps: float, mu: float, nu: float):
    """de Goes & James 2017 regularized Kelvinlet G (N, 3, 3) and its analytic gradient
    (N, 3, 3, 3) for offsets x (N, 3)."""
    a = 1 / (4 * np.pi * mu)
    b = a / (4 * (1 - nu))
    r2 = np.einsum("ni,ni->n", x, x)
    re = np.sqrt(r2 + eps**2)
    eye = np.eye(3)
    scalar = (a - b) / re + a * eps**2 / (2 * re**3)
    green = scalar[:, None, None] * eye + (b / re**3)[:, None, None] * np.einsum("ni,nj->nij", x, x)
    d_scalar = -(a - b) / re**3 - 1.5 * a * eps**2 / re**5  # times x_p
    grad = np.einsum("n,ij,np->nijp", d_scalar, eye, x)
    grad += (b / re**3)[:, None, None, None] * (
        np.einsum("ip,nj->nijp", eye, x) + np.einsum("ni,jp->nijp", x, eye)
    )
    grad -= (3 * b / re**5)[:, None, None, None] * np.einsum("ni,nj,np->nijp", x, x, x)
    return green, grad


def backus_laminate(young=(100.0, 1.0), poisson=(0.3, 0.3), fraction=0.5):
    """Exact effective Voigt stiffness (6, 6) of a two-layer laminate with normal z (MATH.md)."""
    f = np.array([fraction, 1 - fraction])
    e, nu = np.asarray(young, float), np.asarray(poisson, float)
    lam = e * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e / (2 * (1 + nu))

    def avg(v):
        return float(np.dot(f, v))

    c33 = 1 / avg(1 / (lam + 2 * mu))
    ratio = avg(lam / (lam + 2 * mu))
    c13 = ratio * c33
    c11 = avg(4 * mu * (lam + mu) / (lam + 2 * mu)) + ratio**2 * c33
    c12 = c11 - 2 * avg(mu)
    c44 = 1 / avg(1 / mu)
    c66 = avg(mu)
    c6 = np.zeros((6, 6))
    c6[0, 0] = c6[1, 1] = c11
    c6[2, 2] = c33
    c6[0, 1] = c6[1, 0] = c12
    c6[0, 2] = c6[2, 0] = c6[1, 2] = c6[2, 1] = c13
    c6[3, 3] = c6[4, 4] = c44
    c6[5, 5] = c66
    return c6
