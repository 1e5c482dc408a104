#!/usr/bin/env bash
# Configures and builds the release tree into build/ (Ninja; ccache when present).
# Every executable lands in build/bin/. Extra arguments go to the build step (e.g. a target).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release "$@"
echo "build: executables in $(pwd)/build/bin: $(ls build/bin | tr '\n' ' ')"
