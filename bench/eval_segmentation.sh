#!/usr/bin/env bash
# Segmentation quality: the paper's Table III frame scores and
# per-class IoU of the ESPNetv2 network alone and of network + dense CRF, on sequences with
# ground-truth labels: 7-Scenes with composited people (person only: elsewhere the labels are
# unknown) and the synthetic presets (person, chair, tvmonitor). Prints a Markdown table.
# Sequences are cached under $SMAP_EVAL_CACHE (default /tmp/smap-eval-cache), shared with
# eval_dynamic.sh; every $SMAP_SEG_EVERY-th frame is segmented (default 5).
# Usage: bench/eval_segmentation.sh [BUILD_DIR] [extra smap-segment args...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
bin="$build/bin"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
every="${SMAP_SEG_EVERY:-5}"
presets="${SMAP_SEG_PRESETS:-walking_xyz walking_halfsphere sitting_xyz static_xyz}"
shared="$root/../shared"
model="$root/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx"
[ -f "$model" ] || { echo "eval_segmentation: $model not found (the shipped model)" >&2; exit 2; }
mkdir -p "$cache"

# segment NAME INPUT MODE CONFIG... -> OUTDIR (cnn: CRF off; crf: on)
segment() {
    local name="$1" input="$2" mode="$3"
    shift 3
    local out="$cache/seg-$name-$mode" crf=true
    [ "$mode" = cnn ] && crf=false
    rm -rf "$out"
    "$bin/smap-segment" "$@" --config "$root/config/espnetv2_voc.ini" "$input" "$out" \
        --every "$every" --no-overlay --set "onnx.model=$model" --set "crf.enabled=$crf" \
        >/dev/null 2>&1
    echo "$out"
}

# rows NAME INPUT CLASSES VOID CONFIG...: both modes, one table row per class and mode
rows() {
    local name="$1" input="$2" classes="$3" void="$4"
    shift 4
    for mode in cnn crf; do
        out=$(segment "$name" "$input" "$mode" "$@")
        "$bin/smap-eval" segmentation "$input/labels" "$out" --classes "$classes" \
            --void "$void" --json "$out/scores.json" >/dev/null
        /usr/bin/python3 - "$name" "$mode" "$out/scores.json" "$out/segmentation.json" <<'PY'
import json, sys
name, mode, scores, seg = sys.argv[1:5]
s = json.load(open(scores)); t = json.load(open(seg))
label = "CNN" if mode == "cnn" else "CNN + CRF"
f = lambda v: "-" if v is None else "%.3f" % v
for c in s["classes"]:
    print("| %s | %d | %s | %s | %d | %d / %d / %d / %d | %s | %s | %s | %s | %s | %s | %s | %.0f |" % (
        name, s["frames"], label, c["name"], c["tp"] + c["fn"], c["tp"], c["fn"], c["fp"], c["tn"],
        f(c["fpr"]), f(c["fnr"]), f(c["recall"]), f(c["precision"]), f(c["pwc"]), f(c["iou"]),
        f(c["band_iou"]), t["median_ms_per_frame"]))
PY
    done
}

echo "Correctly segmented = IoU >= 0.5; present / predicted = at least 0.1% of the frame; band IoU within 5 px of the true class edges; every ${every}th frame."
echo
echo "| sequence | frames | segmenter | class | frames present | TP / FN / FP / TN | FPR | FNR | Re | Pr | PWC | IoU | band IoU | ms per frame |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
seven="$shared/data/7scenes-redkitchen"
if [ -d "$seven" ] && [ -d "$shared/data/people" ] && [ "${SMAP_EVAL_7SCENES:-1}" = 1 ]; then
    comp="$cache/7scenes-people-colour-1000"
    [ -f "$comp/groundtruth.txt" ] ||
        "$bin/smap-synth" --composite-onto "$seven" --people "$shared/data/people" \
            --config "$root/config/7scenes.ini" --ground-truth "$seven/groundtruth_sfm.txt" \
            --frames 1000 --people-count 4 --out "$comp" --no-rawlog >/dev/null
    # Labels there: 15 on people, 255 (unknown) elsewhere, which is "not person": score all.
    # The composite is registered already: its own camera.ini, not 7scenes.ini.
    rows 7scenes-people "$comp" person none --config "$comp/camera.ini" "$@"
fi
for p in $presets; do
    dir="$cache/$p-300"
    [ -f "$dir/groundtruth.txt" ] ||
        "$bin/smap-synth" --preset "$p" --out "$dir" --frames 300 --no-rawlog >/dev/null
    rows "$p" "$dir" person,chair,tvmonitor 255 --config "$root/config/synthetic.ini" "$@"
done
