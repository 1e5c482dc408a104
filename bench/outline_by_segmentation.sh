#!/usr/bin/env bash
# The keypoint scores (recall 0.95, precision 0.85) against what a segmentation could decide: the 7-Scenes composite
# with four people (as bench/results.sh makes it), tracked once reproducibly with every keypoint
# table written, then the keyframe segmenter (the shipped network + CRF, the main job's
# configuration) run on EVERY frame, as no budget of the main job allows. smap-eval keypoints
# then scores four decisions against the composite's exact masks:
#   1. the filter (the main job's decisions);
#   2. the filter with the outline band (3 px) left out of the scoring (--edge-margin 3);
#   3. a fresh segmentation of the frame alone (--said-by);
#   4. the filter off the band, the fresh segmentation within it (--said-by, second line).
# Last, the segmenter's median time per frame beside the run's per-frame tracking work.
# Usage: bench/outline_by_segmentation.sh [BUILD_DIR] [FRAMES]   (default build/, 1000 frames)
#   SMAP_EVAL_CACHE (default /tmp/smap-eval-cache) keeps the composite and the outputs.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
frames="${2:-1000}"
bin="$build/bin"
shared="${SMAP_SHARED:-$root/../shared}"
kitchen="$shared/data/7scenes-redkitchen"
people="$shared/data/people"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
for d in "$kitchen" "$people"; do
    [ -d "$d" ] || { echo "outline_by_segmentation.sh: $d not found (set SMAP_SHARED)" >&2; exit 2; }
done
comp="$cache/7scenes-people-colour-$frames"
run="$cache/outline-run-$frames"
labels="$cache/outline-labels-$frames"
mkdir -p "$cache"

if [ ! -f "$comp/groundtruth.txt" ]; then
    echo "making the composite in $comp" >&2
    "$bin/smap-synth" --composite-onto "$kitchen" --people "$people" \
        --config "$root/config/7scenes.ini" --ground-truth "$kitchen/groundtruth_sfm.txt" \
        --frames "$frames" --people-count 4 --out "$comp" --no-rawlog >/dev/null
fi
echo "tracking (a reproducible run)" >&2
rm -rf "$run"
"$bin/semantic-mapper" "$comp" --config "$comp/camera.ini" --out "$run" --quiet \
    --set output.snapshots=false --set output.annotated_rawlog=false \
    --reproducible --dynamic-debug all >/dev/null
echo "segmenting every frame" >&2
rm -rf "$labels"
"$bin/smap-segment" --config "$comp/camera.ini" "$comp" "$labels" --no-overlay >/dev/null

gt="$comp/dynamic"
echo "== the filter"
"$bin/smap-eval" keypoints "$gt" "$run/dynamic"
echo "== the filter, the outline band left out"
"$bin/smap-eval" keypoints "$gt" "$run/dynamic" --edge-margin 3 | head -1
echo "== a fresh segmentation of every frame"
"$bin/smap-eval" keypoints "$gt" "$run/dynamic" --said-by "$labels"
# What a segmentation of every frame would cost, beside what each frame costs today.
/usr/bin/python3 - "$labels/segmentation.json" "$run/metrics.json" <<'PY'
import json, sys
seg, t = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))["timings"]
frame = sum(t[k]["median_ms"] for k in ("feature_extraction", "dynamic_filter", "semantic_evidence",
                                         "tracking"))
print("per frame (medians): segmentation %.1f ms; extraction + dynamic filter + semantic "
      "evidence + tracking %.1f ms; the keyframe segmentation in the run %.1f ms"
      % (seg["median_ms_per_frame"], frame, t["segmentation"]["median_ms"]))
PY
