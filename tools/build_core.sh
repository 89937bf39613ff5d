#!/usr/bin/env bash
# Build the compiled core (virtual_actuators._core) in place, for a source tree that is not
# pip-installed (a git worktree, a checkout used with PYTHONPATH): configure and build with CMake
# in build/dev, then copy the extension into virtual_actuators/. About 16 s the first time, a few
# seconds after an edit. PYTHON selects the interpreter (it needs nanobind installed):
#   PYTHON=.venv/bin/python tools/build_core.sh
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
BUILD="${BUILD_DIR:-build/dev}"
generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$BUILD/CMakeCache.txt" ]; then
  generator=(-G Ninja)
fi
cmake -S . -B "$BUILD" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DPython_EXECUTABLE="$("$PYTHON" -c 'import sys; print(sys.executable)')" >/dev/null
cmake --build "$BUILD" --parallel "${JOBS:-2}"
rm -f virtual_actuators/_core.*.so virtual_actuators/_core.*.pyd
cp "$BUILD"/_core.*.so virtual_actuators/ 2>/dev/null || cp "$BUILD"/_core.*.pyd virtual_actuators/
echo "built $(ls virtual_actuators/_core.*)"
