#!/usr/bin/env bash
# Quick start, command 1: install what is needed, then open GoGreen Sculpt.
# Extra arguments go to `gogreen` (for example a mesh file). Without a display, the app runs on a
# virtual X screen (Xvfb).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup_env.sh"
if [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ]; then
    echo "[gogreen] no display found: running on a virtual screen (xvfb-run)"
    exec xvfb-run -a -s "-screen 0 1600x1000x24" "$root/.venv/bin/gogreen" "$@"
fi
exec "$root/.venv/bin/gogreen" "$@"
