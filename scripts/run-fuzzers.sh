#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (+ address/undefined sanitizers) into build-fuzz/ and
# runs each for the given number of seconds (default 10). Any crash, leak or sanitizer report
# fails. Corpora start from the seeds in tests/fuzz/corpus/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
for target in build-fuzz/bin/fuzz_*; do
    name=$(basename "$target")
    corpus="build-fuzz/corpus/$name"
    mkdir -p "$corpus"
    echo "run-fuzzers: $name for ${seconds}s"
    "$target" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -print_final_stats=0 \
        "$corpus" tests/fuzz/corpus 2>&1 | tail -n 3
done
echo "run-fuzzers: no crashes"
