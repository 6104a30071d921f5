"""The start-up status's time left weighs each compile unit by its own expected time (issue 32
item 8): the drivers are most of a first start, so a time per unit said little."""

from __future__ import annotations

import json

import pytest

from gogreen_core import _compiled, compile_times

UNITS = ["drivers", (0, 8), (1, 9), "geometry", "mesh_io", "brushes"]


@pytest.fixture
def cache_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    return tmp_path


def test_the_first_time_the_built_in_weights_say_the_drivers_dominate(cache_folder):
    total = compile_times.seconds_left({}, UNITS, compile_times.recorded())
    assert total == pytest.approx(40.0, rel=0.1)  # a first start on a quiet machine
    # once the drivers are in, most of the time is gone (a per-unit average said 5/6 left)
    after = compile_times.seconds_left({"drivers": 25.0}, UNITS[1:], {})
    assert after < 0.45 * total
    # a busy machine: the drivers took twice as long, so the rest is expected to as well
    slow = compile_times.seconds_left({"drivers": 50.0}, UNITS[1:], {})
    assert slow == pytest.approx(2 * after)
    # a unit the table does not know: no estimate (the driver's per-unit average instead)
    assert compile_times.seconds_left({}, ["someone_else"], {}) is None


def test_measured_times_are_recorded_beside_the_cache_and_used_next_time(cache_folder):
    compile_times.record({"drivers": 12.0, (0, 8): 3.0, "a_test_unit": 5.0})
    data = json.loads((cache_folder / compile_times.FILE_NAME).read_text())
    assert data == {"drivers": 12.0, "angular 0-8": 3.0}  # only the table's units
    known = compile_times.recorded()
    assert compile_times.seconds_left({}, ["drivers", (0, 8)], known) == 15.0


def test_a_progress_report_names_what_is_compiling_and_estimates_from_the_start(cache_folder):
    progress = _compiled.Progress(0, 6, 0.0, tuple(UNITS), 40.0)
    assert progress.seconds_left == 40.0 and progress.compiling == "field drivers"
    assert _compiled.Progress(4, 6, 1.0, ((1, 9),)).compiling == "angular kernel, degrees 1–9"
    assert _compiled.Progress(6, 6, 1.0, ()).compiling == ""
