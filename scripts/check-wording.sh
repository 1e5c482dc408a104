#!/usr/bin/env bash
# Fails when a file of the repository speaks of how it was made rather than of the software:
# work sessions, tracker items by number, "the team". Docs, code, tests and scripts describe
# what the software does and why; dated measurements name a date or a commit.
set -euo pipefail
cd "$(dirname "$0")/.."
pattern='\bsessions?\b|\bissues?[[:space:]]*#?[0-9]+|\bthe team\b'
mapfile -t files < <(git ls-files --cached --others --exclude-standard | grep -v -e '^scripts/check-wording\.sh$' -e '\.onnx$' -e '\.png$' -e '\.jpg$' -e '\.rawlog$' -e '\.gz$')
hits=$(grep -n -i -E -I "$pattern" -- "${files[@]}" 2>/dev/null || true)
if [ -n "$hits" ]; then
    echo "check-wording: the repository should speak of the software only; found:" >&2
    echo "$hits" | head -n 40 >&2
    echo "check-wording: $(echo "$hits" | wc -l) lines" >&2
    exit 1
fi
echo "check-wording: ${#files[@]} files clean"
