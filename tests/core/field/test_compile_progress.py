"""The compile driver counts a compilation's units as they come in (the status bar's "2 of 5
units, about 25 s left")."""

from __future__ import annotations

import pytest

from gogreen_core import _compiled


@pytest.fixture
def fake_units(monkeypatch):
    """Three registered units missing from the disk cache, compiled in this process (mode
    ``thread``: no child); each load advances a fake clock by 4 s."""
    clock = [100.0]
    monkeypatch.setenv("GOGREEN_COMPILE", "thread")
    monkeypatch.setattr(_compiled.time, "perf_counter", lambda: clock[0])
    names = [f"progress_test_{i}" for i in range(3)]

    def load(unit):
        clock[0] += 4.0

    for name in names:
        _compiled.register(name, __name__, load, lambda unit: False)
    yield names
    with _compiled._condition:
        for name in names:
            _compiled._units.pop(name, None)
            _compiled._ready.discard(name)
            _compiled._compiled_units.discard(name)


def test_each_compiled_unit_is_counted_with_the_time_left(fake_units):
    seen: list[_compiled.Progress] = []
    _compiled.add_progress_listener(seen.append)
    try:
        assert _compiled.wait(fake_units, timeout=30)
    finally:
        _compiled.remove_progress_listener(seen.append)
    seen = [p for p in seen if set(p.left) <= set(fake_units)]  # not another test's units
    assert [(p.done, p.total) for p in seen] == [(0, 3), (1, 3), (2, 3), (3, 3)]
    assert seen[0].seconds_left is None  # nothing measured before the first unit is in
    # 4 s per unit so far: 8 s for the two left, then 4 s, then none
    assert [p.seconds_left for p in seen[1:]] == pytest.approx([8.0, 4.0, 0.0])
    assert seen[1].left == tuple(fake_units[1:])
    assert _compiled.compiled_here(fake_units)


def test_units_loaded_from_the_cache_report_no_progress(monkeypatch):
    seen: list[_compiled.Progress] = []
    monkeypatch.setenv("GOGREEN_COMPILE", "thread")
    _compiled.register("progress_test_cached", __name__, lambda unit: None, lambda unit: True)
    _compiled.add_progress_listener(seen.append)
    try:
        assert _compiled.wait(["progress_test_cached"], timeout=30)
        assert not _compiled.compiled_here(["progress_test_cached"])
    finally:
        _compiled.remove_progress_listener(seen.append)
        with _compiled._condition:
            _compiled._units.pop("progress_test_cached", None)
            _compiled._ready.discard("progress_test_cached")
    assert seen == []
