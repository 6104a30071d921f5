"""The ``gogreen`` console script."""

from __future__ import annotations

import argparse
import sys

#: The headless subcommands (gogreen_core.interaction.batch), one help line each.
COMMANDS = {
    "deform": "apply one brush stroke to a mesh and write the result",
    "replay": "replay a session file on a mesh (bit for bit the recorded result)",
    "truncation": "how accurate each l_max is for a material (paper Fig. 9)",
    "recover": "list the crash-recovery journals, or write the mesh or session one recorded",
}


def _parser() -> argparse.ArgumentParser:
    """The parser of ``gogreen [mesh]``; its help also lists the subcommands, which
    :mod:`gogreen_core.interaction.batch` parses (``gogreen COMMAND --help`` shows their
    options)."""
    width = max(len(name) for name in COMMANDS)
    commands = "\n".join(f"  {name:<{width}}  {text}" for name, text in COMMANDS.items())
    each_help = " or ".join(f"`gogreen {name} --help`" for name in COMMANDS)
    parser = argparse.ArgumentParser(
        prog="gogreen",
        usage=f"gogreen [-h] [mesh]\n       gogreen {{{','.join(COMMANDS)}}} ...",
        description="GoGreen Sculpt: opens the sculpting window, on the mesh if one is given.",
        epilog=(
            f"commands (no window is opened):\n{commands}\n\n"
            f"Run {each_help} for a command's own options."
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("mesh", nargs="?", help="mesh file to open (OBJ, PLY, STL, OFF)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """``gogreen [FILE]`` opens the main window; ``gogreen replay|deform|recover ...`` runs
    headless."""
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] in COMMANDS:
        from gogreen_core.interaction.batch import main as batch_main  # no Qt for batch work

        return batch_main(argv)
    args = _parser().parse_args(argv)
    from app.memory import start_lean

    start_lean()  # before the app's imports (app.memory)

    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication

    from app.main_window import MainWindow

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("GoGreen Sculpt")
    window = MainWindow()
    window.show()
    if not (args.mesh and window.files.open_file(args.mesh)):
        window.files.open_default()
    QTimer.singleShot(0, window.crash_recovery.offer)  # unsaved work of a crashed session
    return app.exec()


if __name__ == "__main__":
    sys.exit(main())
