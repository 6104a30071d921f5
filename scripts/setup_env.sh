#!/usr/bin/env bash
# Shared setup for the two quick-start commands: Debian libraries that Qt and VTK load (and GNU
# OpenMP, numba's thread-safe parallel layer: the app runs compiled parallel code on a worker
# thread and the GUI thread at once, which numba's fallback "workqueue" layer aborts on), then a
# virtual environment in .venv with the package installed (editable, with the test extras).
# Safe to run again: each step is skipped when already done.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

debian_packages=(xvfb xauth libgl1 libegl1 libglu1-mesa libxkbcommon-x11-0 libxcb-cursor0
    libxcb-icccm4 libxcb-keysyms1 libxcb-image0 libxcb-render-util0 libxcb-xinerama0
    libxcb-shape0 libxcb-randr0 libxcb-xkb1 libdbus-1-3 libfontconfig1 libxrender1 libxi6
    libgomp1)
if command -v dpkg-query >/dev/null 2>&1; then
    missing=()
    for p in "${debian_packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        echo "[gogreen] installing Debian packages: ${missing[*]}"
        sudo_cmd=""
        [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
        $sudo_cmd apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
    fi
fi

python="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
    echo "[gogreen] creating virtual environment .venv"
    "$python" -m venv .venv
fi
stamp=.venv/.gogreen-installed
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
    echo "[gogreen] installing the package and its dependencies into .venv"
    .venv/bin/python -m pip install -q --upgrade pip
    # The filter hides only setuptools' "Editable installation" notice (information, not a
    # problem: the resources/ folder is mapped to gogreen_resources, so setuptools installs a
    # meta path finder and says so in a box of asterisks that reads like an error).
    .venv/bin/python -W "ignore:Editable installation:UserWarning" -m pip install -q -e ".[test]"
    touch "$stamp"
fi

# The kernels the app's first stroke needs, compiled once into numba's disk cache (a line per
# unit), so that the first window sculpts compiled. Skipped while the stamp is newer than every
# source of gogreen_core (numba recompiles what changed; otherwise the check alone would cost
# the seconds of importing numba on every start). A failure leaves the app working: it
# evaluates in NumPy and compiles in the background. GOGREEN_COMPILE=off skips this step.
kernels_stamp=.venv/.gogreen-kernels
if [ "${GOGREEN_COMPILE:-}" != "off" ] && { [ ! -f "$kernels_stamp" ] ||
    [ -n "$(find gogreen_core -name '*.py' -newer "$kernels_stamp" -print -quit)" ]; }; then
    if .venv/bin/python -m gogreen_core.interaction.compile_kernels; then
        touch "$kernels_stamp"
    fi
fi
