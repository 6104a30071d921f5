"""The generated angular kernels of evaluation 1 (``_legacy.expansion``), kept unchanged.

Frozen with the drivers that call them: the straight-line angular sums per truncation degree
whose arithmetic (under ``fastmath={"contract"}``) produced the results of session files of
versions 1 and 2. ``scripts/make_kernels.py`` writes them to ``gogreen_core/_legacy/angular/``
(``tests/test_unrolled.py`` checks they are fresh). Do not edit the generator.
"""

from __future__ import annotations

import importlib
import threading
from typing import TYPE_CHECKING, Any

from gogreen_core._legacy import expansion as _expansion
from gogreen_core.sph import legendre_recurrence

if TYPE_CHECKING:
    from numba.core.ccallback import CFunc

__all__ = [
    "GENERATED_PACKAGE",
    "UNROLLED_L_MAX",
    "angular_source",
    "generated_modules",
    "module_source",
    "unrolled_angular",
]

#: Highest degree for which kernels are generated; above it the generic kernel serves (the
#: straight-line code, and its compile time, grow as l²).
UNROLLED_L_MAX = 13

_LOCK = threading.Lock()
_KERNELS: dict[tuple[int, int], CFunc[Any]] = {}


def angular_source(l_first: int, l_last: int) -> str:
    """Source of the angular kernel for degrees l_first, l_first + 2, …, l_last (K = 3).

    Every name is assigned once (numba's SSA pass is slow on reassigned names).
    """
    rec = legendre_recurrence(max(l_last, 1))
    degrees = list(range(l_first, l_last + 1, 2))
    base, n_terms = {}, 0
    for l in degrees:
        base[l] = n_terms
        n_terms += 2 * l + 1
    head = [
        "@cfunc(ANGULAR_SIGNATURE, **_JIT)",
        "def angular(nb, geo_ptr, rad_ptr, coeffs_ptr, acc_ptr):",
        f'    """Degrees {l_first}..{l_last} step 2: acc[k, i] = Σ_lm R_l Y_lm coeffs[lm, k]."""',
        f"    rad = carray(rad_ptr, ({len(degrees)}, BLOCK))",
        f"    coeffs = carray(coeffs_ptr, ({n_terms}, 3))",
        "    acc = carray(acc_ptr, (3, BLOCK))",
    ]
    body = ["    for i in range(nb):"]
    if l_last >= 1:  # degree 0 alone does not depend on the direction
        head.insert(3, "    geo = carray(geo_ptr, (8, BLOCK))")
        body += ["        x = geo[0, i]", "        y = geo[1, i]", "        z = geo[2, i]"]
    body += [f"        w{d} = rad[{d}, i]" for d in range(len(degrees))]
    for m in range(l_last + 1):
        scale = float(rec.qmm[m])
        scales = {m: scale}
        for l in range(m + 1, l_last + 1):
            scale *= float(rec.a[l, m])
            scales[l] = scale
            if l == m + 1:
                chain = "z"
            else:
                beta = float(rec.b[l, m] / rec.a[l - 1, m])
                older = repr(beta) if l == m + 2 else f"{beta!r} * p{l - 2}_{m}"
                chain = f"z * p{l - 1}_{m} - {older}"
            body.append(f"        p{l}_{m} = {chain}")
        terms = [l for l in degrees if l >= m]
        parts = (("a", 1),) if m == 0 else (("a", 1), ("b", -1))
        for n, l in enumerate(terms):
            d = degrees.index(l)
            body.append(f"        t{l}_{m} = " + (f"w{d}" if l == m else f"w{d} * p{l}_{m}"))
            for k in range(3):
                for part, sign in parts:
                    coeff = f"{part}c{l}_{m}_{k}"
                    row = base[l] + l + sign * m
                    head.append(f"    {coeff} = coeffs[{row}, {k}] * {scales[l]!r}")
                    prior = f"{part}{m}_{k}_{n - 1} + " if n else ""
                    body.append(f"        {part}{m}_{k}_{n} = {prior}t{l}_{m} * {coeff}")
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
                else (f"u{k}_{m - 1} + cm{m} * a{m}_{k}_{last} + sm{m} * b{m}_{k}_{last}")
            )
            body.append(f"        u{k}_{m} = {total}")
    body += [f"        acc[{k}, i] = u{k}_{l_last}" for k in range(3)]
    return "\n".join(head + body) + "\n"


#: Package holding the generated kernel modules (written by ``scripts/make_kernels.py``).
GENERATED_PACKAGE = "gogreen_core._legacy.angular"


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
    """Text of the generated module for degrees l_first, l_first + 2, …, l_last.

    The block size and compile options of ``_expansion`` are written in as literals, so the
    module's text (which numba's disk cache follows) changes whenever they do, and the freshness
    test catches a module not regenerated since.
    """
    # options are bools, strings and sets of strings: their repr with double quotes is what
    # ruff format writes
    options = ", ".join(f"{k}={v!r}".replace("'", '"') for k, v in _expansion._JIT.items())
    return (
        f'"""Angular kernel for degrees {l_first}..{l_last} step 2. Generated by '
        "scripts/make_kernels.py\nfrom gogreen_core._legacy.unrolled.angular_source: "
        'do not edit."""\n\n'
        "from numba import carray, cfunc\n\n"
        "from gogreen_core._legacy.expansion import ANGULAR_SIGNATURE\n\n"
        f"BLOCK = {_expansion.BLOCK}\n"
        f"_JIT = dict({options})\n\n\n" + angular_source(l_first, l_last)
    )


def unrolled_angular(l_first: int, l_last: int) -> CFunc[Any]:
    """The compiled angular kernel (a numba cfunc) for one parity and highest degree.

    Imports its generated module on first use, which compiles it or loads it from numba's disk
    cache; thread safe.
    """
    if not (l_first in (0, 1) and l_first <= l_last <= UNROLLED_L_MAX and l_last % 2 == l_first):
        raise ValueError(
            f"no generated angular kernel for degrees {l_first}..{l_last} "
            f"(first degree 0 or 1, last of the same parity, at most {UNROLLED_L_MAX})"
        )
    key = (l_first, l_last)
    with _LOCK:
        kernel = _KERNELS.get(key)
        if kernel is None:
            module = importlib.import_module(f"{GENERATED_PACKAGE}.{_module_name(*key)}")
            kernel = _KERNELS[key] = module.angular
        return kernel
