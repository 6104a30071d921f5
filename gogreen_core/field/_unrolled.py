"""Angular kernels generated per truncation degree (three outputs: vector and affine loads).

The generic ``_expansion._angular`` is bound by the loads and stores of its scratch rows; here
the angular sum of one point (paper Eq. 10 or 12) is straight-line code, every intermediate in
a register, vectorized over points. Same IEEE operations in the same order: the same bits.

``scripts/make_kernels.py`` writes one module per (parity, highest degree) into ``_angular``
(committed; a test checks it is fresh); :func:`unrolled_angular` makes its ``angular`` a cached C
callback the drivers take as a first-class function, so only it compiles per degree (in the
background, while the generic kernel serves).

Rescaled recurrence: with P_l = Q_l^m / S_l, S_m = Q_m^m and S_l = a_lm S_{l-1}, the normalized
recurrence Q_l = a_lm (z Q_{l-1} - b_lm Q_{l-2}) of ``sph.py`` becomes
P_l = z P_{l-1} - β_lm P_{l-2} with β_lm = b_lm / a_{l-1,m}, P_m = 1 and P_{m+1} = z; the scales
S_l are folded into the coefficients (:func:`row_scales`). Per order m the degree sums
A_k = Σ_l R_l P_l C_lmk (B_k with the sine coefficients; the first term a plain product) give
u_k = A_k (m = 0) or (u_k + cos mφ A_k) + sin mφ B_k, cos φ = x, sin φ = y and
cos mφ = cos x - sin y, sin mφ = cos y + sin x above.
"""

from __future__ import annotations

import importlib
import threading
from functools import lru_cache
from typing import Any

import numpy as np
from numba import cfunc
from numba.core import sigutils
from numba.core.ccallback import CFunc

from gogreen_core.field import _expansion
from gogreen_core.physics.sph import legendre_recurrence

__all__ = [
    "GENERATED_PACKAGE",
    "UNROLLED_L_MAX",
    "angular_cached",
    "angular_constants",
    "angular_source",
    "generated_modules",
    "module_source",
    "row_scales",
    "unrolled_angular",
]

#: Highest degree for which kernels are generated; above it the generic kernel serves (the
#: straight-line code, and its compile time, grow as l²).
UNROLLED_L_MAX = 13


@lru_cache(maxsize=8)
def angular_constants(l_last: int) -> tuple[np.ndarray, np.ndarray]:
    """(β, S), each (L+1, L+1) with L = max(l_last, 1): the rescaled recurrence constants
    β[l, m] = b_lm / a_{l-1,m} (l ≥ m + 2) and the scales S[l, m] = Q_m^m Π_{j=m+1..l} a_jm
    (l ≥ m), as the generated kernels have them written in (read-only arrays)."""
    size = max(l_last, 1) + 1
    rec = legendre_recurrence(size - 1)
    beta = np.zeros((size, size))
    scales = np.zeros((size, size))
    for m in range(size):
        scale = float(rec.qmm[m])
        scales[m, m] = scale
        for l in range(m + 1, size):
            scale *= float(rec.a[l, m])
            scales[l, m] = scale
            if l >= m + 2:
                beta[l, m] = float(rec.b[l, m] / rec.a[l - 1, m])
    beta.setflags(write=False)
    scales.setflags(write=False)
    return beta, scales


def row_scales(l_first: int, l_last: int) -> np.ndarray:
    """S for each coefficient row of the parity (rows of degree l: m = -l … l), to fold into
    the coefficients: (Σ (2l+1),)."""
    _, scales = angular_constants(l_last)
    return np.concatenate(
        [[scales[l, abs(m)] for m in range(-l, l + 1)] for l in range(l_first, l_last + 1, 2)]
    )


def angular_source(l_first: int, l_last: int, single: bool = False) -> str:
    """Source of the angular kernel for degrees l_first, l_first + 2, …, l_last (K = 3): the
    operations of ``_expansion._angular``, unrolled, every name assigned once (numba's SSA pass
    is slow on reassigned names). ``single``: the streamlines' ``angular_single``, in float32
    and without degree l_first (the velocity adds it in double precision)."""
    beta, _ = angular_constants(l_last)
    degrees = list(range(l_first, l_last + 1, 2))
    base, n_terms = {}, 0
    for l in degrees:
        base[l] = n_terms
        n_terms += 2 * l + 1
    summed = degrees[1:] if single else degrees
    name, what = ("angular_single", "single precision, ") if single else ("angular", "")
    low = summed[0] if summed else l_first

    def constant(value: float) -> str:
        return f"F({value!r})" if single else repr(value)

    doc = f"Degrees {l_first}..{l_last} step 2: acc[k, i] = Σ_lm R_l Y_lm coeffs[lm, k]."
    if single:
        doc = (
            f"Degrees {low}..{l_last} step 2 ({what}coefficient rows of degrees "
            f"{l_first}..{l_last}):\n    acc[k, i] = Σ_lm R_l Y_lm coeffs[lm, k]."
        )
    head = [
        f"def {name}(nb, geo_ptr, rad_ptr, coeffs_ptr, acc_ptr):",
        f'    """{doc}"""',
        f"    rad = carray(rad_ptr, ({len(summed)}, BLOCK))",
        f"    coeffs = carray(coeffs_ptr, ({n_terms}, 3))",
        "    acc = carray(acc_ptr, (3, BLOCK))",
    ]
    body = ["    for i in range(nb):"]
    if l_last >= 1:  # degree 0 alone does not depend on the direction
        head.insert(3, "    geo = carray(geo_ptr, (8, BLOCK))")
        body += ["        x = geo[0, i]", "        y = geo[1, i]", "        z = geo[2, i]"]
    body += [f"        w{d} = rad[{d}, i]" for d in range(len(summed))]
    for m in range(l_last + 1):
        for l in range(m + 1, l_last + 1):
            if l == m + 1:
                chain = "z"
            elif l == m + 2:  # P_m = 1, and β · 1 = β exactly
                chain = f"z * p{l - 1}_{m} - {constant(float(beta[l, m]))}"
            else:
                chain = f"z * p{l - 1}_{m} - {constant(float(beta[l, m]))} * p{l - 2}_{m}"
            body.append(f"        p{l}_{m} = {chain}")
        terms = [l for l in summed if l >= m]
        parts = (("a", 1),) if m == 0 else (("a", 1), ("b", -1))
        for n, l in enumerate(terms):
            d = summed.index(l)
            body.append(f"        t{l}_{m} = " + (f"w{d}" if l == m else f"w{d} * p{l}_{m}"))
            for k in range(3):
                for part, sign in parts:
                    coeff = f"{part}c{l}_{m}_{k}"
                    head.append(f"    {coeff} = coeffs[{base[l] + l + sign * m}, {k}]")
                    value = (
                        f"{part}{m}_{k}_{n - 1} + t{l}_{m} * {coeff}"
                        if n
                        else f"t{l}_{m} * {coeff}"
                    )
                    body.append(f"        {part}{m}_{k}_{n} = {value}")
        last = len(terms) - 1
        if m == 1:
            body += ["        cm1 = x", "        sm1 = y"]
        elif m > 1:
            body.append(f"        cm{m} = cm{m - 1} * x - sm{m - 1} * y")
            body.append(f"        sm{m} = cm{m - 1} * y + sm{m - 1} * x")
        for k in range(3):
            total = (
                f"a0_{k}_{last}"
                if m == 0
                else f"(u{k}_{m - 1} + cm{m} * a{m}_{k}_{last}) + sm{m} * b{m}_{k}_{last}"
            )
            body.append(f"        u{k}_{m} = {total}")
    body += [f"        acc[{k}, i] = u{k}_{l_last}" for k in range(3)]
    return "\n".join(head + body) + "\n"


#: Package holding the generated kernel modules (written by ``scripts/make_kernels.py``).
GENERATED_PACKAGE = f"{__name__.rpartition('.')[0]}._angular"  # beside this module


def _module_name(l_first: int, l_last: int) -> str:
    return f"degrees_{l_first}_{l_last}"


def generated_modules() -> dict[str, str]:
    """Module name → source text of every generated kernel: each parity (first degree 0 or 1)
    with each highest degree up to :data:`UNROLLED_L_MAX`."""
    return {
        _module_name(l_first, l_last): module_source(l_first, l_last)
        for l_first in (0, 1)
        for l_last in range(l_first, UNROLLED_L_MAX + 1, 2)
    }


def module_source(l_first: int, l_last: int) -> str:
    """Text of the generated module for degrees l_first, l_first + 2, …, l_last: ``angular``
    and, with more than one degree, ``angular_single``. The block size and compile options are
    literals in it, so its text (which numba's disk cache follows) changes with them."""
    # options are bools and strings: their repr with double quotes is what ruff format writes
    options = ", ".join(f"{k}={v!r}".replace("'", '"') for k, v in _CALLBACK_OPTIONS.items())
    single = l_last > l_first
    return (
        f'"""Angular kernels for degrees {l_first}..{l_last} step 2. Generated by '
        f'scripts/make_kernels.py\nfrom {__name__}.angular_source: do not edit."""\n\n'
        "from numba import carray\n"
        + ("from numpy import float32 as F\n" if single else "")
        + f"\nBLOCK = {_expansion.BLOCK}\n"
        f"#: Options of the C callbacks {__name__} makes of the kernels.\n"
        f"OPTIONS = dict({options})\n\n\n"
        + angular_source(l_first, l_last)
        + ("\n\n" + angular_source(l_first, l_last, single=True) if single else "")
    )


#: Compile options of the generated C callbacks: those of the drivers (no fastmath); cached.
_CALLBACK_OPTIONS = {
    k: v for k, v in _expansion._JIT.items() if k in ("boundscheck", "error_model")
}


#: Compiled kernels by (l_first, l_last, single).
_KERNELS: dict[tuple[int, int, bool], CFunc[Any]] = {}
#: Held while a generated kernel is compiled (or loaded); never while only looking one up.
_COMPILE_LOCK = threading.Lock()


def _check(l_first: int, l_last: int, single: bool = False) -> tuple[int, int]:
    if not (l_first in (0, 1) and l_first <= l_last <= UNROLLED_L_MAX and l_last % 2 == l_first):
        raise ValueError(
            f"no generated angular kernel for degrees {l_first}..{l_last} "
            f"(first degree 0 or 1, last of the same parity, at most {UNROLLED_L_MAX})"
        )
    if single and l_last == l_first:
        raise ValueError(f"no single precision angular kernel for degree {l_first} alone")
    return l_first, l_last


def _callback(key: tuple[int, int], single: bool) -> tuple[Any, Any, dict[str, Any]]:
    """(the generated module's kernel function, its C signature, its compile options)."""
    module = importlib.import_module(f"{GENERATED_PACKAGE}.{_module_name(*key)}")
    if single:
        return module.angular_single, _expansion.ANGULAR_SINGLE_SIGNATURE, module.OPTIONS
    return module.angular, _expansion.ANGULAR_SIGNATURE, module.OPTIONS


def unrolled_angular(l_first: int, l_last: int, single: bool = False) -> CFunc[Any]:
    """The compiled angular kernel (a numba cfunc) for one parity and highest degree (``single``:
    the streamlines' float32 one), compiled or loaded from numba's disk cache; thread safe."""
    key = (*_check(l_first, l_last, single), single)
    kernel = _KERNELS.get(key)
    if kernel is None:
        with _COMPILE_LOCK:
            kernel = _KERNELS.get(key)
            if kernel is None:
                function, signature, options = _callback(key[:2], single)
                make = cfunc(signature, cache=True, **options)
                kernel = _KERNELS[key] = make(function)
    return kernel


def angular_cached(l_first: int, l_last: int, single: bool = False) -> bool:
    """Whether numba's disk cache holds the compiled kernel (nothing is compiled). Uses
    numba's cache of C callbacks directly (``CFunc._cache``, not public API)."""
    key = (*_check(l_first, l_last, single), single)
    if key in _KERNELS:
        return True
    function, signature, options = _callback(key[:2], single)
    callback: Any = CFunc(function, sigutils.normalize_signature(signature), {}, options)
    callback.enable_caching()
    context = callback._targetdescr.target_context
    return callback._cache.load_overload(callback._sig, context) is not None
