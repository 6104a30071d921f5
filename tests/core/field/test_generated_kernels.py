"""Generated angular kernels: their source files, compilation and caching."""

import importlib
import inspect
import os
import subprocess
import sys
from pathlib import Path

import pytest

from gogreen_core.field import _expansion, _unrolled
from gogreen_core.field.kernel import prepare_degree


def test_shipped_kernels_are_fresh():
    """The committed modules equal what scripts/make_kernels.py writes now, and no stale module
    is left (run the script after changing the generator, BLOCK or the compile options)."""
    generator = _unrolled
    folder = Path(importlib.import_module(generator.GENERATED_PACKAGE).__path__[0])
    expected = generator.generated_modules()
    shipped = {path.stem: path.read_text(encoding="utf-8") for path in folder.glob("*.py")}
    assert shipped.pop("__init__", None) is not None
    assert sorted(shipped) == sorted(expected)
    stale = [name for name, text in expected.items() if shipped[name] != text]
    assert not stale, f"regenerate with `python scripts/make_kernels.py`: {stale} differ"


def test_integrator_carries_the_stamp_of_the_sources_it_compiles():
    """_integrator's compiled code is cached on its own file's stamp, but built with
    _expansion's functions: a change there must show here
    (scripts/make_kernels.py)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "scripts"))
    from make_kernels import sources_stamp

    from gogreen_core.field import _integrator

    assert _integrator.COMPILED_SOURCES == sources_stamp(), "run scripts/make_kernels.py"


def test_module_text_carries_block_size_and_options(monkeypatch):
    # numba's disk cache follows the module's own text: what the kernel is compiled with must
    # be in it, so a change cannot be served stale machine code.
    text = _unrolled.module_source(0, 4)
    assert "carray(rad_ptr, (3, BLOCK))" in text and "def angular(" in text
    assert f"BLOCK = {_expansion.BLOCK}\n" in text
    assert 'OPTIONS = dict(boundscheck=False, error_model="numpy")' in text
    assert "fastmath" not in text  # no contraction: the NumPy evaluation must match it
    assert _unrolled.module_source(1, 5) != text
    monkeypatch.setattr(_expansion, "BLOCK", 2 * _expansion.BLOCK)
    assert _unrolled.module_source(0, 4) != text


def test_kernels_come_from_the_package_and_bad_degrees_are_refused():
    kernel = _unrolled.unrolled_angular(0, 2)
    assert _unrolled.unrolled_angular(0, 2) is kernel
    assert _unrolled.angular_cached(0, 2)
    assert "gogreen_core.field._angular.degrees_0_2" in sys.modules
    source = inspect.getsource(_unrolled)
    assert "tempfile" not in source and "gettempdir" not in source
    for first, last in ((0, 3), (2, 4), (1, _unrolled.UNROLLED_L_MAX + 2), (0, -2)):
        with pytest.raises(ValueError, match="no generated angular kernel"):
            _unrolled.unrolled_angular(first, last)


def test_compiled_kernels_are_cached_by_numba_where_it_is_told(tmp_path):
    """A fresh process compiles a shipped kernel into numba's cache (NUMBA_CACHE_DIR here; by
    default __pycache__ beside the module or numba's per-user cache), nowhere else, and a
    second process finds it there without compiling."""
    script = (
        "import sys, gogreen_core.field._unrolled as u; cached = u.angular_cached(0, 0); "
        "u.unrolled_angular(0, 0); print(cached, u.angular_cached(0, 0))"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    for expected in ("False True", "True True"):
        result = subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
        )
        assert result.stdout.strip().splitlines()[-1] == expected
    index = [p.name for p in tmp_path.rglob("*.nbi")]
    assert any(name.startswith("degrees_0_0.angular") for name in index), index


def test_prepare_degree():
    assert prepare_degree(7) >= 0.0  # the app's background step: brings the code in
    # each unit: the double precision kernel and evaluation 3's single precision one
    assert {(0, 6, False), (0, 6, True), (1, 7, False), (1, 7, True)} <= set(_unrolled._KERNELS)
    prepare_degree(20)  # above UNROLLED_L_MAX: the generic kernel serves, nothing generated
    assert not any(last > _unrolled.UNROLLED_L_MAX for _, last, _ in _unrolled._KERNELS)
