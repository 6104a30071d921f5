"""README.md's examples run as written after the quick start: its bash lines that call
``.venv/bin/...`` and its Python blocks, in a fresh folder whose ``.venv`` is the environment
running the tests."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gogreen_core.mesh.mesh_io import load_mesh

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```$", README, flags=re.S | re.M)


def _venv_commands() -> list[str]:
    return [
        line
        for block in _blocks("bash")
        for line in block.splitlines()
        if line.startswith(".venv/bin/")
    ]


@pytest.fixture
def fresh_folder(tmp_path: Path) -> Path:
    """An empty folder with ``.venv`` linked to the environment running the tests."""
    venv = Path(sys.prefix)
    if venv == Path(sys.base_prefix) or not (venv / "bin" / "gogreen").exists():
        pytest.skip("needs the tests to run in the virtual environment the quick start makes")
    (tmp_path / ".venv").symlink_to(venv, target_is_directory=True)
    return tmp_path


def _run_ok(command: list[str], folder: Path) -> None:
    """Run ``command`` in ``folder`` as a user would; fail with its stderr if it fails."""
    result = subprocess.run(
        command, cwd=folder, capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL
    )
    assert result.returncode == 0, result.stderr[-2000:]


def test_the_readme_calls_commands_through_the_venv():
    for block in _blocks("bash"):
        for line in block.splitlines():
            command = line.split("#")[0].split()
            assert not command or command[0] in ("bash", "source") or "/" in command[0], line
    assert [c.split()[1] for c in _venv_commands() if c.startswith(".venv/bin/gogreen")] == [
        "deform",
        "deform",
        "deform",
        "replay",
    ]


def test_the_readme_command_line_examples_run_as_written(fresh_folder):
    script = "set -euo pipefail\n" + "\n".join(_venv_commands()) + "\n"
    _run_ok(["bash", "-c", script], fresh_folder)
    pebble = load_mesh(fresh_folder / "pebble.obj").vertices
    pulled = load_mesh(fresh_folder / "pulled.obj").vertices
    twisted = load_mesh(fresh_folder / "twisted.obj").vertices
    replayed = load_mesh(fresh_folder / "replayed.ply").vertices
    assert np.abs(pulled - pebble).max() > 0.1  # the grab moved the top
    assert np.abs(twisted - pebble).max() > 0.01
    assert np.array_equal(replayed, pulled)  # "bit for bit"


def test_the_readme_python_examples_run_as_written(fresh_folder):
    core, sculpting, presets = _blocks("python")
    python = str(fresh_folder / ".venv" / "bin" / "python")
    for script in (core, sculpting + presets):  # the presets example continues the one before
        _run_ok([python, "-c", script], fresh_folder)
    assert load_mesh(fresh_folder / "out.ply").vertices.shape == (40962, 3)
    assert (fresh_folder / "my_wood.json").is_file()
