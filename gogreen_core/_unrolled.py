"""Angular kernels generated for one truncation degree (three outputs: vector and affine loads).

The generic ``_expansion._angular`` runs the Legendre recurrence over scratch rows, one pass per
(l, m): its loads and stores of those rows, not arithmetic, bound it. Here the angular sum of
one point (paper Eq. 10 or 12 up to a given degree) is written out as straight-line code, so
every intermediate stays in a register and LLVM vectorizes the one loop left, over points.

The source is generated per (parity, highest degree) with the recurrence constants as literals,
written to a cache directory (a real file, so that numba's ``cache=True`` keeps the machine code
on disk) and compiled as a C callback of ``_expansion.ANGULAR_SIGNATURE``; the drivers
``expand`` and ``stream`` take it as a first-class function, so only this function is compiled
per degree (measured: 1.1 s for both parities at l_max 4, 3.0 s at 8, 6.6 s at 12; once per
machine, then loaded from the cache in milliseconds).

Rescaled recurrence: with P_l = Q_l^m / S_l, S_m = Q_m^m and S_l = a_lm S_{l-1}, the normalized
recurrence Q_l = a_lm (z Q_{l-1} - b_lm Q_{l-2}) of ``sph.py`` becomes
P_l = z P_{l-1} - (b_lm / a_{l-1,m}) P_{l-2} with P_m = 1 and P_{m+1} = z; the scales S_l are
folded into the coefficients once per block. Per order m the degree sums A_k = Σ_l R_l P_l C_lmk
(and B_k with the sine coefficients) are combined as cos mφ A_k + sin mφ B_k.
"""

from __future__ import annotations

import hashlib
import importlib.util
import inspect
import os
import sys
import tempfile
import threading
from pathlib import Path

from gogreen_core import _expansion
from gogreen_core.sph import legendre_recurrence

__all__ = ["UNROLLED_L_MAX", "angular_source", "unrolled_angular"]

#: Highest degree for which kernels are generated; above it the generic kernel serves (the
#: straight-line code, and its compile time, grow as l²).
UNROLLED_L_MAX = 13

_LOCK = threading.Lock()
_KERNELS: dict[tuple[int, int], object] = {}


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
        "    geo = carray(geo_ptr, (8, BLOCK))",
        f"    rad = carray(rad_ptr, ({len(degrees)}, BLOCK))",
        f"    coeffs = carray(coeffs_ptr, ({n_terms}, 3))",
        "    acc = carray(acc_ptr, (3, BLOCK))",
    ]
    body = [
        "    for i in range(nb):",
        "        x = geo[0, i]",
        "        y = geo[1, i]",
        "        z = geo[2, i]",
    ]
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


def _module_source(l_first: int, l_last: int) -> str:
    # numba's disk cache does not follow what the module imports, so the text (hence the file
    # name) carries a digest of _expansion.py and of this generator: editing either regenerates.
    digest = hashlib.sha1()
    for module in (_expansion, sys.modules[__name__]):
        digest.update(inspect.getsource(module).encode())
    return (
        f'"""Generated by gogreen_core._unrolled (degrees {l_first}..{l_last} step 2, sources '
        f'{digest.hexdigest()[:12]}). Do not edit."""\n\n'
        "from numba import carray, cfunc\n\n"
        "from gogreen_core._expansion import _JIT, ANGULAR_SIGNATURE, BLOCK\n\n\n"
        + angular_source(l_first, l_last)
    )


def _cache_dirs() -> list[Path]:
    configured = os.environ.get("GOGREEN_KERNEL_DIR")
    if configured:
        return [Path(configured)]
    xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    fallback = Path(tempfile.gettempdir()) / "gogreen-kernels"
    return [Path(xdg) / "gogreen-sculpt" / "kernels", fallback]


def _write_source(text: str, name: str) -> Path:
    errors = []
    for directory in _cache_dirs():
        path = directory / f"{name}.py"
        try:
            directory.mkdir(parents=True, exist_ok=True)
            if path.exists() and path.read_text(encoding="utf-8") == text:
                return path  # unchanged: keeps its time stamp, so numba's cache stays valid
            # atomic, so that a concurrent process never imports a half-written module
            fd, tmp = tempfile.mkstemp(dir=directory, suffix=".tmp")
            with os.fdopen(fd, "w", encoding="utf-8") as handle:
                handle.write(text)
            os.replace(tmp, path)
            return path
        except OSError as error:
            errors.append(f"{directory}: {error}")
    raise OSError("no writable directory for generated kernels: " + "; ".join(errors))


def unrolled_angular(l_first: int, l_last: int):
    """The compiled angular kernel (a numba cfunc) for one parity and highest degree.

    Generated, written and compiled (or loaded from numba's cache) on first use; thread safe.
    """
    key = (l_first, l_last)
    with _LOCK:
        kernel = _KERNELS.get(key)
        if kernel is None:
            text = _module_source(l_first, l_last)
            digest = hashlib.sha1(text.encode()).hexdigest()[:12]
            name = f"gogreen_angular_{l_first}_{l_last}_{digest}"
            spec = importlib.util.spec_from_file_location(name, _write_source(text, name))
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            spec.loader.exec_module(module)
            kernel = _KERNELS[key] = module.angular
        return kernel
