#!/usr/bin/env bash
# Runs clang-tidy (.clang-tidy) over the project's C++ sources using build/compile_commands.json.
# Fails on any finding. Arguments: files to check (default: every .cpp under libs/ and apps/).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/compile_commands.json ] || cmake --preset release >/dev/null
if [ $# -gt 0 ]; then files=("$@"); else mapfile -t files < <(git ls-files --cached --others --exclude-standard 'libs/*.cpp' 'apps/*.cpp'); fi
printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -n 4 clang-tidy -p build --quiet 2>/dev/null | tee /tmp/smap-tidy.log
if grep -qE '(warning|error):' /tmp/smap-tidy.log; then
    echo "check-tidy: findings above" >&2
    exit 1
fi
echo "check-tidy: ${#files[@]} files clean"
