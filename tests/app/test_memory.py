"""The app keeps no copies of its modules' sources (issue 36, item 4): PySide6's import hook
reads each module imported after it to see whether it names PySide6, and linecache kept them
all (about 70 MB); nor pyvista's mypy plugin. No RSS figures here: benchmarks/app_scale.py
prints those."""

from __future__ import annotations

import linecache
import subprocess
import sys

from app.memory import read_sources_uncached, release_freed_memory


def _import_from(folder, name: str, text: str):
    (folder / f"{name}.py").write_text(text)
    sys.path.insert(0, str(folder))
    try:
        exec(f"import {name}", {})  # through the import statement, as PySide6's hook sees it
    finally:
        sys.path.remove(str(folder))
        sys.modules.pop(name, None)
    return str(folder / f"{name}.py")


def test_pyside_answers_its_question_without_keeping_the_source(tmp_path):
    assert read_sources_uncached()
    assert read_sources_uncached()  # a second call keeps the one hook
    feature = sys.modules["shibokensupport.feature"]
    names_qt = _import_from(tmp_path, "gogreen_test_names_qt", "import PySide6  # noqa\n")
    plain = _import_from(tmp_path, "gogreen_test_plain", "ANSWER = 42\n")
    assert names_qt not in linecache.cache and plain not in linecache.cache
    # the hook's answers as before: a module naming PySide6 takes part in feature switching
    assert feature.pyside_feature_dict["gogreen_test_names_qt"] == 0
    assert feature.pyside_feature_dict["gogreen_test_plain"] == -1


def test_release_drops_the_cached_sources_and_tracebacks_still_read_them(tmp_path):
    path = tmp_path / "some_module.py"
    path.write_text("first = 1\nsecond = 2\n")
    assert linecache.getline(str(path), 2) == "second = 2\n"
    assert str(path) in linecache.cache
    release_freed_memory(collect=False)
    assert str(path) not in linecache.cache
    assert linecache.getline(str(path), 2) == "second = 2\n"  # read again when asked


def test_the_app_starts_without_pyvistas_mypy_plugin():
    # in a process of its own: the app's start (app.cli.main) before pyvista is imported
    code = (
        "import sys\nfrom app.memory import start_lean\nstart_lean()\nimport pyvista\n"
        "print(sorted(name for name, module in sys.modules.items() if name.startswith('mypy') "
        "and module is not None))"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split() == ["[]"]


def test_the_window_releases_once_a_new_surface_index_is_in(window, qtbot, tmp_path):
    path = tmp_path / "read_by_a_traceback.py"
    path.write_text("line = 1\n")
    linecache.getline(str(path), 1)
    sculptor = window.document.sculptor
    # as an opened mesh is: its surface index built on the background thread
    window.viewport.set_mesh(sculptor.vertices, sculptor.faces, background=True)
    assert str(path) in linecache.cache  # nothing released while the index builds
    qtbot.waitUntil(lambda: str(path) not in linecache.cache, timeout=60_000)
    assert not window.viewport.surface_building
