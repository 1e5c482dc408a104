#!/usr/bin/env bash
# An installed semantic-mapper finds its model and sample recording relative to its prefix, not
# in the source or build tree: install into a fresh prefix, move the prefix (so no path of the
# installation is compiled in either), and run the main job on 20 frames of the sample.
# Usage: installed_programs_find_their_data.sh BUILD_DIR WORK_DIR
set -euo pipefail
build="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
mv "$work/prefix" "$work/moved"
out=$(cd "$work" && "$work/moved/bin/semantic-mapper" --out "$work/out" \
    --set input.max_frames=20 --set output.snapshots=false 2>&1)
echo "$out" | grep -F "loaded $work/moved/share/semantic-mapper/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx" >/dev/null ||
    { echo "$out"; echo "FAIL: the installed model was not loaded"; exit 1; }
echo "$out" | grep -F "reading rawlog '$work/moved/share/semantic-mapper/rawlogs/sample_walking_xyz.rawlog'" >/dev/null ||
    { echo "$out"; echo "FAIL: the installed sample was not read"; exit 1; }
grep -q '"frames": 20' "$work/out/metrics.json" || { echo "FAIL: metrics.json"; exit 1; }
# smap-synth draws its people from the installed cut-outs.
"$work/moved/bin/smap-synth" --preset walking_static --frames 2 --size 160x120 --no-rawlog \
    --contact-sheet 0 --out "$work/synth" >/dev/null
[ -f "$work/synth/rgb/000001.png" ] || { echo "FAIL: smap-synth"; exit 1; }
echo "installed programs found their data under $work/moved/share/semantic-mapper"
