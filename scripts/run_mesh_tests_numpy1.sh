#!/usr/bin/env bash
# The mesh file tests (tests/test_mesh_io*.py) under numpy 1.26, the numpy of Blender's own
# Python, where a Blender extension of this project will import gogreen_core. A small second
# virtual environment in .venv-numpy1: numpy 1.26 and the core's other dependencies (versions
# from pyproject.toml), the package itself without the GUI's. CI runs it after the README's test
# command (.ci/run). Safe to run again: the environment is made once. Extra arguments go to pytest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
python="${PYTHON:-python3}"
venv=.venv-numpy1
if [ ! -x "$venv/bin/python" ]; then
    echo "[gogreen] creating $venv (numpy 1.26) for the mesh tests"
    "$python" -m venv "$venv"
fi
stamp="$venv/.gogreen-installed"
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
    core=$("$venv/bin/python" - <<'PY'
import re
import tomllib

with open("pyproject.toml", "rb") as handle:
    project = tomllib.load(handle)["project"]
wanted = {"numpy", "scipy", "numba", "mapbox-earcut"}  # what gogreen_core imports
tests = project["optional-dependencies"]["test"]
for requirement in project["dependencies"] + tests:
    if re.split(r"[<>=!~ ;\[]", requirement, maxsplit=1)[0].lower() in wanted | {"pytest"}:
        print(requirement)
PY
)
    # shellcheck disable=SC2086
    "$venv/bin/python" -m pip install -q $core "numpy>=1.26,<2"
    "$venv/bin/python" -W "ignore:Editable installation:UserWarning" -m pip install -q --no-deps -e .
    touch "$stamp"
fi
"$venv/bin/python" -c "import numpy; print('[gogreen] mesh tests under numpy', numpy.__version__)"
# Compiled code of its own: numba's cache holds code built against the other environment.
export NUMBA_CACHE_DIR="$root/$venv/numba-cache"
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider tests/test_mesh_io*.py "$@"
