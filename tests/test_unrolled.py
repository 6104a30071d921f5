"""Generated angular kernels: their source files, and agreement with the generic kernel."""

import inspect
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gogreen_core import _expansion, _unrolled
from gogreen_core.kernel import GreenKernel, prepare_degree
from gogreen_core.material import Material


def test_shipped_kernels_are_fresh():
    """The committed modules equal what scripts/make_kernels.py writes now, and no stale module
    is left (run the script after changing the generator, BLOCK or the compile options)."""
    folder = Path(_unrolled.__file__).parent / "_angular"
    expected = _unrolled.generated_modules()
    shipped = {path.stem: path.read_text(encoding="utf-8") for path in folder.glob("*.py")}
    assert shipped.pop("__init__", None) is not None
    assert sorted(shipped) == sorted(expected)
    stale = [name for name, text in expected.items() if shipped[name] != text]
    assert not stale, f"regenerate with `python scripts/make_kernels.py`: {stale} differ"


def test_module_text_carries_block_size_and_options(monkeypatch):
    # numba's disk cache follows the module's own text: what the kernel is compiled with must
    # be in it, so a change cannot be served stale machine code.
    text = _unrolled.module_source(0, 4)
    assert "ANGULAR_SIGNATURE" in text and "carray(rad_ptr, (3, BLOCK))" in text
    assert f"BLOCK = {_expansion.BLOCK}\n" in text and "cache=True" in text
    assert _unrolled.module_source(1, 5) != text
    monkeypatch.setattr(_expansion, "BLOCK", 2 * _expansion.BLOCK)
    assert _unrolled.module_source(0, 4) != text


def test_kernels_come_from_the_package_and_bad_degrees_are_refused():
    kernel = _unrolled.unrolled_angular(0, 2)
    assert _unrolled.unrolled_angular(0, 2) is kernel
    assert "gogreen_core._angular.degrees_0_2" in sys.modules
    source = inspect.getsource(_unrolled)
    assert "tempfile" not in source and "gettempdir" not in source
    for first, last in ((0, 3), (2, 4), (1, _unrolled.UNROLLED_L_MAX + 2), (0, -2)):
        with pytest.raises(ValueError, match="no generated angular kernel"):
            _unrolled.unrolled_angular(first, last)


def test_compiled_kernels_are_cached_by_numba_where_it_is_told(tmp_path):
    """A fresh process compiles a shipped kernel into numba's cache (NUMBA_CACHE_DIR here; by
    default __pycache__ beside the module or numba's per-user cache), nowhere else."""
    script = "import gogreen_core._unrolled as u; u.unrolled_angular(0, 0); print('ok')"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    result = subprocess.run(
        [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
    )
    assert result.stdout.split()[-1] == "ok"
    index = [p.name for p in tmp_path.rglob("*.nbi")]
    assert any(name.startswith("degrees_0_0.angular") for name in index), index


@pytest.mark.parametrize("parity", [0, 1])
def test_generated_and_generic_angular_agree(parity):
    """Same drivers, the generated angular kernel against the generic one, bit-level close."""
    kernel = GreenKernel(Material.cubic(3.0, 1.5, 0.4), l_max=10)
    part = kernel._even if parity == 0 else kernel._odd
    tables = kernel._even_tables if parity == 0 else kernel._odd_tables
    rng = np.random.default_rng(parity)
    points = rng.normal(size=(1000, 3)) * 2.0
    points[0] = 0.0
    coeffs = np.ascontiguousarray(rng.normal(size=(part.matrices.shape[0], 3)))
    qmm, rec_a, rec_b = kernel._recurrence
    results = []
    for angular, unrolled in (part.angular(3), (_expansion.generic_marker, False)):
        out = np.empty((len(points), 3))
        _expansion.expand(
            points, np.zeros(3), 1.0, 1 + parity, part.l_first, part.l_last, part.base,
            coeffs, tables, qmm, rec_a, rec_b, angular, unrolled, out,
        )  # fmt: skip
        results.append(out)
    assert np.allclose(results[0], results[1], rtol=1e-13, atol=1e-15 * abs(results[1]).max())
    assert not np.array_equal(results[0], results[1])  # two implementations, not one twice


def test_warm_up_and_prepare_degree():
    seconds = GreenKernel(Material.isotropic(1.0, 0.3), l_max=3).warm_up()
    assert 0.0 < seconds < 600.0
    assert prepare_degree(7) >= 0.0  # the app's background step: compiles only
    assert {(0, 6), (1, 7)} <= set(_unrolled._KERNELS)
    prepare_degree(20)  # above UNROLLED_L_MAX: the generic kernel serves, nothing generated
    assert not any(last > _unrolled.UNROLLED_L_MAX for _, last in _unrolled._KERNELS)
