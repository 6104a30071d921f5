"""The install step's compilation (``python -m gogreen_core.interaction.compile_kernels``, run
by scripts/setup_env.sh): what the app's first stroke needs, first; a line per unit."""

from __future__ import annotations

from pathlib import Path

from gogreen_core import _compiled
from gogreen_core.field import _drivers
from gogreen_core.interaction import compile_kernels


def test_the_first_stroke_units_come_first_and_every_app_unit_is_there():
    units = compile_kernels.units_for_app(8)
    assert units[0] == _compiled.DRIVERS  # every brush event evaluates with them
    assert set(units[: len(_drivers.units_for(8))]) == set(_drivers.units_for(8))
    assert {_compiled.GEOMETRY, _compiled.BRUSHES, _compiled.MESH_IO} <= set(units)
    assert len(set(units)) == len(units)


def test_a_line_per_unit_compiled_with_the_time_left(capsys):
    lines = compile_kernels._Lines()
    units = compile_kernels.units_for_app(8)
    lines(_compiled.Progress(0, 3, 0.0, units[:3]))
    lines(_compiled.Progress(1, 3, 10.0, units[1:3]))
    lines(_compiled.Progress(3, 3, 24.0, ()))
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "[gogreen] compiling the kernels once (3 units; numba keeps them on disk)"
    assert out[1] == "[gogreen]   1/3 field drivers: 10.0 s, about 20 s left"
    assert out[2].startswith("[gogreen]   3/3 angular kernel, degrees ")
    assert out[2].endswith(f", {compile_kernels.unit_name(units[2])}: 24.0 s")


def test_the_install_step_runs_it_and_the_app_asks_in_the_same_order():
    root = Path(__file__).resolve().parents[3]
    setup = (root / "scripts/setup_env.sh").read_text()
    assert "-m gogreen_core.interaction.compile_kernels" in setup
    warmup = (root / "app/kernel_warmup.py").read_text()
    assert "units_for_app(l_max)" in warmup
