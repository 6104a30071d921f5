"""Generated angular kernels: their source files, and agreement with the generic kernel."""

import numpy as np
import pytest

from gogreen_core import _expansion, _unrolled
from gogreen_core.kernel import GreenKernel, prepare_degree
from gogreen_core.material import Material


def test_source_file_is_written_once_and_atomically(tmp_path, monkeypatch):
    monkeypatch.setenv("GOGREEN_KERNEL_DIR", str(tmp_path / "kernels"))
    path = _unrolled._write_source("x = 1\n", "gogreen_angular_test")
    assert path.parent == tmp_path / "kernels" and path.read_text() == "x = 1\n"
    stamp = path.stat().st_mtime_ns
    # unchanged text keeps the file (and its time stamp: numba's cache stays valid)
    assert _unrolled._write_source("x = 1\n", "gogreen_angular_test") == path
    assert path.stat().st_mtime_ns == stamp
    _unrolled._write_source("x = 2\n", "gogreen_angular_test")
    assert path.read_text() == "x = 2\n"
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no temporary left


def test_unwritable_kernel_directory_is_named(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("GOGREEN_KERNEL_DIR", str(blocker / "kernels"))
    with pytest.raises(OSError, match=r"no writable directory for generated kernels.*file"):
        _unrolled._write_source("x = 1\n", "gogreen_angular_test")


def test_module_text_depends_on_the_drivers_source():
    # The file name carries a digest of _expansion.py, so numba's cache cannot serve code
    # compiled against older drivers.
    text = _unrolled._module_source(0, 4)
    assert "ANGULAR_SIGNATURE" in text and "carray(rad_ptr, (3, BLOCK))" in text
    assert _unrolled._module_source(0, 4) == text
    assert _unrolled._module_source(1, 5) != text


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
