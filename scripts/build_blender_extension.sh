#!/usr/bin/env bash
# Build the Blender extension packages into dist/ (see scripts/build_blender_extension.py; its
# options pass through, e.g. --platform linux-x64). Needs Python >= 3.11 with pip: .venv's when
# the quick start made it, else python3.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
python="${PYTHON:-python3}"
[ -x "$root/.venv/bin/python" ] && python="$root/.venv/bin/python"
exec "$python" "$root/scripts/build_blender_extension.py" "$@"
