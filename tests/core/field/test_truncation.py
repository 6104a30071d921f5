"""The truncation readout (paper Fig. 9): δ(l_max) of a material, checked against an independent
plane-wave evaluation of G that uses no spherical harmonics (tests/helpers/green_reference.py)."""

import json
import subprocess
import sys

import numpy as np
import pytest
from green_reference import backus_laminate, reference_green

from gogreen_core import GaussianRadial, GreenKernel, Material
from gogreen_core.field.truncation import (
    TruncationCancelled,
    TruncationReport,
    _sample_points,
    truncation_errors,
)
from gogreen_core.validation import ParameterError

CUBIC = Material.from_voigt(
    np.array(
        [
            [3.0, 1.5, 1.5, 0, 0, 0],
            [1.5, 3.0, 1.5, 0, 0, 0],
            [1.5, 1.5, 3.0, 0, 0, 0],
            [0, 0, 0, 0.4, 0, 0],
            [0, 0, 0, 0, 0.4, 0],
            [0, 0, 0, 0, 0, 0.4],
        ]
    )
)


def _independent_error(material: Material, l_max: int, report: TruncationReport) -> float:
    """δ(l_max) with the plane-wave G in place of the high-degree expansion, at the centre and
    at the 24 sample points where the truncated expansion differs most from the readout's
    reference (a plane-wave evaluation costs ~10 ms a point, so not at all of them)."""
    points = _sample_points(report.reference_degree)
    truncated = GreenKernel(material, l_max, GaussianRadial(1.0)).green(points)
    reference = GreenKernel(material, report.reference_degree, GaussianRadial(1.0)).green(points)
    worst = np.argsort(-np.linalg.norm((truncated - reference).reshape(-1, 9), axis=1))[:24]
    chosen = np.concatenate([[0], worst])  # point 0 is the centre
    exact = np.array([reference_green(material, points[i], 1.0)[0] for i in chosen])
    difference = np.linalg.norm((truncated[chosen] - exact).reshape(-1, 9), axis=1).max()
    return difference / np.linalg.norm(exact[0])


@pytest.mark.parametrize(
    ("material", "degrees"),
    [(CUBIC, (2, 4, 8)), (Material.from_voigt(backus_laminate(young=(100.0, 1.0))), (4, 8))],
    ids=["cubic", "laminate"],
)
def test_the_readout_agrees_with_an_independent_evaluation(material, degrees):
    report = truncation_errors(material, max_degree=12)
    for l_max in degrees:
        independent = _independent_error(material, l_max, report)
        assert report.error(l_max) == pytest.approx(independent, rel=0.1), l_max


def test_an_isotropic_material_is_exact_from_degree_two():
    report = truncation_errors(Material.isotropic(2.0, 0.35), max_degree=10)
    assert report.errors[0] > 1e-2  # l_max 0 misses the anisotropic part of G
    assert np.all(report.errors[1:] < 1e-12)
    assert report.suggested() == 2


def test_errors_fall_with_the_degree_and_the_suggestion_meets_the_tolerance():
    report = truncation_errors(CUBIC, max_degree=16)
    assert np.all(np.diff(report.errors) < 0)
    assert list(report.degrees) == list(range(0, 17, 2))
    best = report.suggested(1e-3)
    assert report.error(best) <= 1e-3 < report.error(best - 2)
    assert report.error(best + 1) == report.error(best)  # odd l_max: G has no odd degrees
    assert report.error(40) == report.errors[-1]  # beyond the range: the last value
    assert "enough" in report.summary(16) and "exact to the eye" in report.summary(best)
    assert "brings it under" in report.summary(2)
    assert "lowers it to" in report.summary(2, tolerance=1e-12)


def test_progress_and_cancel():
    calls = []
    truncation_errors(CUBIC, max_degree=4, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    with pytest.raises(TruncationCancelled):
        truncation_errors(CUBIC, max_degree=4, cancelled=lambda: True)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"max_degree": -2}, "max_degree"),
        ({"max_degree": 50}, "max_degree"),
    ],
)
def test_bad_arguments_name_the_parameter(kwargs, name):
    with pytest.raises(ParameterError) as info:
        truncation_errors(CUBIC, **kwargs)
    assert info.value.parameter == name


def test_command_line_prints_the_curve_and_the_advice(tmp_path):
    material = tmp_path / "cubic.json"
    material.write_text(json.dumps(CUBIC.to_dict()))
    run = subprocess.run(
        [sys.executable, "-m", "app.cli", "truncation", "--material", str(material), "-q"],
        capture_output=True,
        text=True,
        check=True,
    )
    lines = run.stdout.splitlines()
    assert lines[1].split() == ["l_max", "error"]
    assert len(lines) == 2 + 11 + 1
    expected = truncation_errors(CUBIC, max_degree=20)
    assert lines[-1] == expected.summary(8)
    assert float(lines[2 + 4].split()[1]) == pytest.approx(expected.error(8), rel=1e-2)
    bad = subprocess.run(
        [sys.executable, "-m", "app.cli", "truncation", "--young", "-1"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and "--young/--poisson" in bad.stderr
