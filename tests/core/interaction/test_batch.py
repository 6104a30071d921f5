"""Headless command line: gogreen deform and gogreen replay."""

import json
import subprocess
import sys

import numpy as np
import pytest

from gogreen_core.interaction.batch import main
from gogreen_core.mesh.mesh_io import load_mesh
from gogreen_core.sculpt.sculptor import Sculptor


@pytest.fixture(params=["made", "stanford-bunny.obj"])
def bunny(request, made_open_tiny, shared_mesh) -> str:
    """The shared bunny (skipped when absent) or its stand-in: open and tiny (conftest.py)."""
    return str(made_open_tiny.path if request.param == "made" else shared_mesh(request.param))


def test_deform_then_replay_reproduce_bit_for_bit(tmp_path, capsys, bunny):
    out, session = tmp_path / "out.ply", tmp_path / "session.json"
    center = load_mesh(bunny).vertices[100]
    status = main(
        [
            "deform",
            bunny,
            "-o",
            str(out),
            "--brush",
            "grab_biscale",
            "--events",
            "5",
            "--center",
            *map(str, center),
            "--delta",
            "0",
            "0.01",
            "0.003",
            "--young",
            "2",
            "--poisson",
            "0.45",
            "--symmetry",
            "x",
            "--session-out",
            str(session),
        ]
    )
    assert status == 0
    assert "deform [" in capsys.readouterr().err  # progress bar
    deformed = load_mesh(out)
    assert np.abs(deformed.vertices[100] - center - [0, 0.01, 0.003]).max() < 1e-9
    replayed = tmp_path / "replayed.ply"
    assert main(["replay", str(session), bunny, "-o", str(replayed)]) == 0
    assert np.array_equal(load_mesh(replayed).vertices, deformed.vertices)


def test_bad_input_exits_nonzero_with_a_message_and_keeps_the_output(tmp_path, capsys, bunny):
    out = tmp_path / "out.obj"
    out.write_text("precious")
    assert (
        main(
            [
                "deform",
                bunny,
                "-o",
                str(out),
                "--center",
                "0",
                "0",
                "0",
                "--delta",
                "0",
                "0.01",
                "0",
                "--radius",
                "0",
            ]
        )
        == 2
    )
    assert "radius" in capsys.readouterr().err
    assert (
        main(
            [
                "deform",
                bunny,
                "-o",
                str(out),
                "--center",
                "0",
                "0",
                "0",
                "--delta",
                "0",
                "0.01",
                "0",
                "--poisson",
                "0.7",
            ]
        )
        == 2
    )
    assert "poisson" in capsys.readouterr().err.lower()
    broken = tmp_path / "broken.obj"
    broken.write_text("v 1 2\n")
    assert (
        main(
            [
                "deform",
                str(broken),
                "-o",
                str(out),
                "--center",
                "0",
                "0",
                "0",
                "--delta",
                "0",
                "1",
                "0",
            ]
        )
        == 2
    )
    assert "broken.obj" in capsys.readouterr().err
    session = tmp_path / "s.json"
    session.write_text("{not json")
    assert main(["replay", str(session), bunny, "-o", str(out)]) == 2
    assert "not valid JSON" in capsys.readouterr().err
    session.write_text(
        json.dumps({"format": "gogreen-session", "version": 1, "mesh": {"vertices": 3, "faces": 1}})
    )
    assert main(["replay", str(session), bunny, "-o", str(out)]) == 2
    assert "settings is missing" in capsys.readouterr().err
    triangle = Sculptor(np.eye(3), [[0, 1, 2]])
    session.write_text(json.dumps(triangle.session()))
    assert main(["replay", str(session), bunny, "-o", str(out)]) == 2
    assert "3 vertices" in capsys.readouterr().err
    assert out.read_text() == "precious"


def test_console_script_runs_batch_without_qt(tmp_path, bunny):
    code = (
        "import sys; from app.cli import main; "
        "rc = main(['deform', sys.argv[1], '-o', sys.argv[2], '-q', '--brush', 'twist', "
        "'--center', '0', '0.1', '0', '--amount', '0.3']); "
        "assert 'PySide6' not in sys.modules; sys.exit(rc)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code, bunny, str(tmp_path / "t.obj")], capture_output=True, text=True
    )
    assert result.returncode == 0, result.stderr
    assert load_mesh(tmp_path / "t.obj").vertices.shape == load_mesh(bunny).vertices.shape
