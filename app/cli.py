"""The ``gogreen`` console script."""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str] | None = None) -> int:
    """``gogreen [FILE]`` opens the main window; ``gogreen replay|deform ...`` runs headless."""
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] in ("replay", "deform"):
        from gogreen_core.batch import main as batch_main  # no Qt for batch work

        return batch_main(argv)
    parser = argparse.ArgumentParser(prog="gogreen", description="GoGreen Sculpt")
    parser.add_argument("mesh", nargs="?", help="mesh file to open (OBJ, PLY, STL, OFF)")
    args = parser.parse_args(argv)
    from PySide6.QtWidgets import QApplication

    from app.main_window import MainWindow

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("GoGreen Sculpt")
    window = MainWindow()
    window.show()
    if not (args.mesh and window.open_file(args.mesh)):
        window.open_default()
    return app.exec()


if __name__ == "__main__":
    sys.exit(main())
