"""The ``gogreen`` console script's help: the window's ``[mesh]`` and the headless commands."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

from app.cli import COMMANDS, main
from gogreen_core.interaction import batch


def _help(capsys, argv: list[str]) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 0
    return capsys.readouterr().out


def test_top_level_help_lists_each_command_on_one_line_and_how_to_get_its_help(capsys):
    text = _help(capsys, ["--help"])
    assert "mesh file to open" in text
    lines = text.splitlines()
    width = max(len(name) for name in COMMANDS)
    for name, summary in COMMANDS.items():
        wanted = [f"  {name:<{width}}  {summary}"]
        assert [line for line in lines if line.split()[:1] == [name]] == wanted
        assert f"`gogreen {name} --help`" in text
    assert "gogreen {" + ",".join(COMMANDS) + "} ..." in text  # in the usage too
    assert _help(capsys, ["-h"]) == text


def test_the_listed_commands_are_the_ones_the_batch_parser_runs():
    subparsers = [
        action
        for action in batch._parser()._actions
        if isinstance(action, argparse._SubParsersAction)
    ]
    assert len(subparsers) == 1
    assert set(subparsers[0].choices) == set(COMMANDS)


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_each_command_keeps_its_own_help(capsys, name):
    text = _help(capsys, [name, "--help"])
    assert text.startswith(f"usage: gogreen {name} ")
    if name != "truncation":  # it prints its table
        assert "-o OUTPUT" in text


def test_help_opens_no_window_and_loads_no_qt():
    code = (
        "import sys\n"
        "from app.cli import main\n"
        "try:\n"
        "    main(['--help'])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 0, exc.code\n"
        "print('PySide6' in sys.modules)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert result.stdout.strip().splitlines()[-1] == "False"
