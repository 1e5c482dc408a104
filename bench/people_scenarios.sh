#!/usr/bin/env bash
# Table II of issue 34: the kinds of human motion, composited into the 7-Scenes frames
# (smap-synth --composite-onto --scenario, colour camera geometry, SfM poses; cached under
# $SMAP_EVAL_CACHE, default /tmp/smap-eval-cache), each tracked without people (the same frames
# of the original recording), with the filter off, in the paper's mode, in the default mode
# without semantic evidence, and in the default mode. Prints a Markdown table: frames with a
# pose, ATE RMSE against the SfM reference, whether it is within max(1.5 x, + 1 cm) of the
# people-free run, dynamic-keypoint recall / precision (default modes), and the people left in
# the point map (bench/map_ghosts.py against the people-free map; default modes).
# Usage: bench/people_scenarios.sh [BUILD_DIR] [extra semantic-mapper args...]
#   SMAP_SCENARIOS="NAME:FRAMES ..." (default: crossing:300 crowd:234 seated:500 stop_and_stay:450)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
bin="$build/bin"
shared="${SMAP_SHARED:-$root/../shared}"
kitchen="$shared/data/7scenes-redkitchen"
people="$shared/data/people"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
scenarios="${SMAP_SCENARIOS:-crossing:300 crowd:234 seated:500 stop_and_stay:450}"
for d in "$kitchen" "$people"; do
    [ -d "$d" ] || { echo "people_scenarios.sh: $d not found (set SMAP_SHARED)" >&2; exit 2; }
done
mkdir -p "$cache"
out="$(mktemp -d "${TMPDIR:-/tmp}/smap-scenarios.XXXXXX")"
trap 'rm -rf "$out"' EXIT

track() {  # input config output extra...
    local input="$1" config="$2" o="$3"
    shift 3
    "$bin/semantic-mapper" "$input" --config "$config" --out "$o" --quiet \
        --set output.snapshots=false --set output.annotated_rawlog=false "$@" >/dev/null
}
rmse() { "$bin/smap-eval" ate "$1" "$2" | awk '/rmse/ {printf "%.4f", $2}'; }
within() { awk -v a="$1" -v b="$2" 'BEGIN {m = 1.5 * b; if (b + 0.01 > m) m = b + 0.01;
                                          print (a <= m ? "yes" : "no")}'; }
keypoints() {
    "$bin/smap-eval" keypoints "$1/dynamic" "$2/dynamic" |
        awk '/recall/ {printf "%.3f / %.3f", $4, $6}'
}
ghosts() {
    "${SMAP_SYSTEM_PYTHON:-/usr/bin/python3}" "$root/bench/map_ghosts.py" \
        "$1/semantic_points.ply" "$2/semantic_points.ply" |
        awk '/ghosts/ {for (i = 1; i <= NF; i++) if ($i == "ghosts") {print $(i + 2); exit}}' |
        tr -d '(;'
}

echo "| scenario | frames | run | with pose | ATE (m) | within max(1.5x, +1 cm) of no people | keypoints recall / precision | people left in point map |"
echo "|---|---|---|---|---|---|---|---|"
for s in $scenarios; do
    name="${s%%:*}" frames="${s##*:}"
    dir="$cache/scen-$name"
    if [ ! -f "$dir/groundtruth.txt" ]; then
        echo "compositing $name ($frames frames) ..." >&2
        "$bin/smap-synth" --composite-onto "$kitchen" --people "$people" \
            --config "$root/config/7scenes.ini" --ground-truth "$kitchen/groundtruth_sfm.txt" \
            --frames "$frames" --seed 1 --scenario "$name" --no-rawlog --out "$dir" >/dev/null
    fi
    free="$out/$name-free"
    track "$kitchen" "$root/config/7scenes.ini" "$free" --set "input.max_frames=$frames" "$@"
    freeAte="$(rmse "$dir/groundtruth.txt" "$free/trajectory.txt")"
    echo "| $name | $frames | no people | $(grep -vc '^#' "$free/trajectory.txt") | $freeAte | - | - | - |"
    for run in off paper default-no-semantic default; do
        o="$out/$name-$run"
        case "$run" in
            off) track "$dir" "$dir/camera.ini" "$o" --set dynamic.mode=off "$@" ;;
            paper) track "$dir" "$dir/camera.ini" "$o" --config "$root/config/modes/paper.ini" "$@" ;;
            default-no-semantic)
                track "$dir" "$dir/camera.ini" "$o" --dynamic-debug all \
                    --set semantic_evidence.enabled=false "$@" ;;
            default) track "$dir" "$dir/camera.ini" "$o" --dynamic-debug all "$@" ;;
        esac
        ate="$(rmse "$dir/groundtruth.txt" "$o/trajectory.txt")"
        kp="-" gh=""
        if [ -d "$o/dynamic" ]; then
            kp="$(keypoints "$dir" "$o")"
            gh="$(ghosts "$free" "$o")"
        fi
        [ -n "$gh" ] && gh="$gh %" || gh="-"
        echo "| $name | $frames | $run | $(grep -vc '^#' "$o/trajectory.txt") | $ate | $(within "$ate" "$freeAte") | $kp | $gh |"
    done
done
