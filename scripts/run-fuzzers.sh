#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (+ address/undefined sanitizers) into build-fuzz/ and
# runs each for the given number of seconds (default 10). Any crash, leak or sanitizer report
# fails. Corpora start from the seeds in tests/fuzz/seeds/<target>/ when the target has its own
# (the frame sources: images of a TUM folder, pieces of the sample rawlog), else from the text
# seeds in tests/fuzz/corpus/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
# An allocation above 256 MB fails (malloc returns null, new throws: tests/fuzz/AllocationLimit.cpp)
# as on a memory-limited robot computer, instead of being reported: MRPT's deserializer trusts
# the sizes in a damaged rawlog, and the readers must survive the failure.
export ASAN_OPTIONS="allocator_may_return_null=1:max_allocation_size_mb=256${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
# Leaks inside MRPT that no reader can avoid are listed, with their reasons, in
# tests/fuzz/lsan.supp; anything else still fails.
export LSAN_OPTIONS="suppressions=$(pwd)/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
for target in build-fuzz/bin/fuzz_*; do
    name=$(basename "$target")
    corpus="build-fuzz/corpus/$name"
    seeds="tests/fuzz/seeds/$name"
    [ -d "$seeds" ] || seeds=tests/fuzz/corpus
    mkdir -p "$corpus"
    echo "run-fuzzers: $name for ${seconds}s (seeds: $seeds)"
    "$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=0 \
        "$corpus" "$seeds" 2>&1 | tail -n 3
done
echo "run-fuzzers: no crashes"
