#!/usr/bin/env bash
# Robustness where people fill much of the view: composites of ../shared/data/people walked
# through the 1000 7-Scenes frames (smap-synth --composite-onto, cached under
# $SMAP_EVAL_CACHE, default /tmp/smap-eval-cache; made in the colour camera's geometry with
# the SfM poses), tracked with the dynamic filter. Prints per composite the frames with a pose,
# the ATE against the 7-Scenes SfM reference (the composite's ground truth), and the ATE
# against this build's own run on the people-free frames (same settings): the second removes
# the reference's own error and shows what the people cost.
# Usage: bench/crowded_composites.sh [BUILD_DIR] [extra semantic-mapper args...]
#   SMAP_COMPOSITES="SEED:PEOPLE ..." (default: 1:4 3:2 5:4 7:3 9:4 13:4 21:3)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
bin="$build/bin"
shared="${SMAP_SHARED:-$root/../shared}"
kitchen="$shared/data/7scenes-redkitchen"
people="$shared/data/people"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
composites="${SMAP_COMPOSITES:-1:4 3:2 5:4 7:3 9:4 13:4 21:3}"
for d in "$kitchen" "$people"; do
    [ -d "$d" ] || { echo "crowded_composites.sh: $d not found (set SMAP_SHARED)" >&2; exit 2; }
done
mkdir -p "$cache"
out="$(mktemp -d "${TMPDIR:-/tmp}/smap-crowded.XXXXXX")"
trap 'rm -rf "$out"' EXIT

track() {  # input config output extra...
    local input="$1" config="$2" o="$3"
    shift 3
    "$bin/semantic-mapper" "$input" --config "$config" --out "$o" --quiet \
        --set segmentation.backend=none --set output.snapshots=false \
        --set output.annotated_rawlog=false "$@" >/dev/null
}
rmse() { "$bin/smap-eval" ate "$1" "$2" | awk '/rmse/ {print $2}'; }

echo "people-free 7-Scenes run (reference) ..." >&2
track "$kitchen" "$root/config/7scenes.ini" "$out/reference" "$@"
printf '%-16s %8s %12s %16s\n' composite tracked "ATE_gt_m" "ATE_vs_free_m"
printf '%-16s %8s %12s %16s\n' people-free \
    "$(grep -vc '^#' "$out/reference/trajectory.txt")" \
    "$(rmse "$kitchen/groundtruth_sfm.txt" "$out/reference/trajectory.txt")" 0
for c in $composites; do
    seed="${c%%:*}" n="${c##*:}"
    dir="$cache/composite-colour-s$seed-p$n"
    if [ ! -f "$dir/groundtruth.txt" ]; then
        echo "compositing seed $seed, $n people ..." >&2
        "$bin/smap-synth" --composite-onto "$kitchen" --people "$people" \
            --config "$root/config/7scenes.ini" --ground-truth "$kitchen/groundtruth_sfm.txt" \
            --frames 1000 --seed "$seed" \
            --people-count "$n" --no-rawlog --out "$dir" >/dev/null
    fi
    track "$dir" "$dir/camera.ini" "$out/s$seed" "$@"
    printf '%-16s %8s %12s %16s\n' "seed$seed-${n}p" \
        "$(grep -vc '^#' "$out/s$seed/trajectory.txt")" \
        "$(rmse "$dir/groundtruth.txt" "$out/s$seed/trajectory.txt")" \
        "$(rmse "$out/reference/trajectory.txt" "$out/s$seed/trajectory.txt")"
done
