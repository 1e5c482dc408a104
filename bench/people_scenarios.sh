#!/usr/bin/env bash
# Table II for the kinds of human motion: composited into the 7-Scenes frames
# (smap-synth --composite-onto --scenario, colour camera geometry, SfM poses), and the synthetic
# presets with people (smap-synth --preset); sequences cached under $SMAP_EVAL_CACHE (default
# /tmp/smap-eval-cache). Each is tracked without people (the same frames of the original
# recording; for a preset its static twin, the same camera motion in the same room), with the
# filter off, in the paper's mode, in the default mode without semantic evidence, and in the
# default mode. Prints a Markdown table: frames with a pose (and the longest stretch without
# one, smap-eval ate's longest gap), ATE RMSE against the ground truth
# (the SfM reference for 7-Scenes), whether it is within max(1.5 x, + 1 cm) of the people-free
# run, dynamic-keypoint recall / precision (default modes; with the outline bound, the best
# precision at recall 0.95 a decision by motion reaches, smap-eval keypoints), and the people
# left in the point map and in the octomap's occupied voxels (bench/map_ghosts.py against the
# people-free maps, with the shares where a person was and on a person, composites and presets;
# default modes).
# Usage: bench/people_scenarios.sh [BUILD_DIR] [extra semantic-mapper args...]
#   SMAP_SCENARIOS="NAME:FRAMES[:DISTANCE_SCALE] ..." (default: crossing:300 crowd:234
#   crowd:234:1.7 seated:500 stop_and_stay:450; smap-synth --distance-scale, 1.7 puts the crowd
#   where it covers up to about half the view)
#   SMAP_PRESETS="NAME ..." (default: walking_xyz walking_halfsphere sitting_xyz; 300 frames)
#   SMAP_RUNS="RUN ..." (default: off paper default-no-semantic default): the runs with people
#   Extra arguments apply to every run, e.g. --set input.stride=2 (every other frame: 15 Hz).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
bin="$build/bin"
shared="${SMAP_SHARED:-$root/../shared}"
kitchen="$shared/data/7scenes-redkitchen"
people="$shared/data/people"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
scenarios="${SMAP_SCENARIOS-crossing:300 crowd:234 crowd:234:1.7 seated:500 stop_and_stay:450}"
presets="${SMAP_PRESETS-walking_xyz walking_halfsphere sitting_xyz}"
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
ateRmse() { awk '/rmse/ {printf "%.4f", $2}'; }  # smap-eval ate's report on stdin
rmse() { "$bin/smap-eval" ate "$1" "$2" | ateRmse; }
# trajectory, smap-eval ate's report on stdin -> "N" poses, "N (no pose for frames A-B)" for the
# longest gap
atePosed() {
    awk -v n="$(grep -vc '^#' "$1")" '/longest gap/ {gsub(/,/, "", $10); g = " (no pose for frames " $10 ")"}
                                      END {printf "%s%s", n, g}'
}
within() { awk -v a="$1" -v b="$2" 'BEGIN {m = 1.5 * b; if (b + 0.01 > m) m = b + 0.01;
                                          print (a <= m ? "yes" : "no")}'; }
keypoints() {  # "recall / precision (bound P)": P, smap-eval's outline bound at recall 0.95
    "$bin/smap-eval" keypoints "$1/dynamic" "$2/dynamic" |
        awk '/^frames/ {printf "%.3f / %.3f", $4, $6}
             /^outline bound/ {for (i = 1; i < NF; i++) if ($i == "precision") b = $(i + 1)}
             END {if (b != "") printf " (bound %.3f)", b}'
}
# ghosts free run, run, map file [folder] -> "x.xx %" and, given the smap-synth folder (composite
# or preset), " (y.yy % where a
# person was; on a person z.zzz %)", for an octomap " (y.yy % where a person was; on a person
# seen free without people: N voxels)" (bench/map_ghosts.py)
ghosts() {
    local people=()
    [ -n "${4:-}" ] && people=(--people "$4")
    "${SMAP_SYSTEM_PYTHON:-/usr/bin/python3}" "$root/bench/map_ghosts.py" "$1/$3" "$2/$3" "${people[@]}" |
        awk '/ghosts/ {for (i = 1; i <= NF; i++) {
                 if ($i == "ghosts") all = $(i + 2)
                 if ($i == "was") near = $(i + 2)
                 if ($i == "surface") surf = $(i + 2)
                 if ($i == "people" && $(i - 1) == "without") free = $(i + 1)}
             gsub(/[(;,]/, "", all); gsub(/[(;,]/, "", near); gsub(/[(;,]/, "", surf)
             printf "%s %%", all
             if (near != "" && free != "")
                 printf " (%s %% where a person was; on a person seen free without people: %s voxels)", near, free
             else if (near != "")
                 printf " (%s %% where a person was; on a person %s %%)", near, surf
             exit}'
}
. "$root/bench/twins.sh"
render() {  # preset -> its folder (300 frames, cached)
    local dir="$cache/$1-300"
    [ -f "$dir/groundtruth.txt" ] ||
        "$bin/smap-synth" --preset "$1" --out "$dir" --frames 300 --no-rawlog >/dev/null
    echo "$dir"
}

# rows NAME FRAMES DIR CONFIG FREE_RUN FREE_ATE FOLDER|"" [args]: the four runs with people
rows() {
    local name="$1" frames="$2" dir="$3" config="$4" free="$5" freeAte="$6" composite="$7"
    shift 7
    for run in ${SMAP_RUNS:-off paper default-no-semantic default}; do
        local o="$out/$name-$run"
        case "$run" in
            off) track "$dir" "$config" "$o" --set dynamic.mode=off "$@" ;;
            paper) track "$dir" "$config" "$o" --config "$root/config/modes/paper.ini" "$@" ;;
            default-no-semantic)
                track "$dir" "$config" "$o" --dynamic-debug all \
                    --set semantic_evidence.enabled=false "$@" ;;
            default) track "$dir" "$config" "$o" --dynamic-debug all "$@" ;;
        esac
        local report ate kp="-" gh="-" go="-"
        report="$("$bin/smap-eval" ate "$dir/groundtruth.txt" "$o/trajectory.txt")"
        ate="$(ateRmse <<<"$report")"
        if [ -d "$o/dynamic" ]; then
            kp="$(keypoints "$dir" "$o")"
            gh="$(ghosts "$free" "$o" semantic_points.ply "$composite")"
            go="$(ghosts "$free" "$o" semantic_octomap.bt "$composite")"
        fi
        echo "| $name | $frames | $run | $(atePosed "$o/trajectory.txt" <<<"$report") | $ate | $(within "$ate" "$freeAte") | $kp | $gh | $go |"
    done
}

echo "| sequence | frames | run | with pose | ATE (m) | within max(1.5x, +1 cm) of no people | keypoints recall / precision | people left in point map | in octomap (occupied voxels) |"
echo "|---|---|---|---|---|---|---|---|---|"
for s in $scenarios; do
    IFS=: read -r scenario frames scale <<<"$s"
    name="$scenario" dir="$cache/scen-$scenario"
    if [ -n "$scale" ]; then
        name="$scenario-x$scale" dir="$cache/scen-$scenario-d$scale-s1"
    fi
    if [ ! -f "$dir/groundtruth.txt" ]; then
        echo "compositing $name ($frames frames) ..." >&2
        "$bin/smap-synth" --composite-onto "$kitchen" --people "$people" \
            --config "$root/config/7scenes.ini" --ground-truth "$kitchen/groundtruth_sfm.txt" \
            --frames "$frames" --seed 1 --scenario "$scenario" --distance-scale "${scale:-1}" \
            --no-rawlog --out "$dir" >/dev/null
    fi
    free="$out/$name-free"
    track "$kitchen" "$root/config/7scenes.ini" "$free" --set "input.max_frames=$frames" "$@"
    freeAte="$(rmse "$dir/groundtruth.txt" "$free/trajectory.txt")"
    echo "| $name | $frames | no people | $(grep -vc '^#' "$free/trajectory.txt") | $freeAte | - | - | - | - |"
    rows "$name" "$frames" "$dir" "$dir/camera.ini" "$free" "$freeAte" "$dir" "$@"
done
synthetic="$root/config/synthetic.ini"
for p in $presets; do
    t="$(twin "$p")"
    [ -n "$t" ] || { echo "people_scenarios.sh: no static twin for preset $p" >&2; exit 2; }
    dir="$(render "$p")"
    tdir="$(render "$t")"
    free="$out/$p-free"
    track "$tdir" "$synthetic" "$free" "$@"
    freeAte="$(rmse "$tdir/groundtruth.txt" "$free/trajectory.txt")"
    echo "| $p | 300 | no people ($t) | $(grep -vc '^#' "$free/trajectory.txt") | $freeAte | - | - | - | - |"
    rows "$p" 300 "$dir" "$synthetic" "$free" "$freeAte" "$dir" "$@"
done
