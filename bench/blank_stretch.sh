#!/usr/bin/env bash
# Robustness check: a copy of a TUM folder (symlinks) where frames [FIRST, FIRST+COUNT) are
# replaced by a black colour image and an all-zero depth image; runs semantic-mapper on it and
# prints the status of every frame around the stretch and the ATE of what was tracked against
# each reference the folder has.
# Usage: bench/blank_stretch.sh [TUM_DIR] [FIRST] [COUNT] [CONFIG]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
src="${1:-$root/../shared/data/7scenes-redkitchen}"
first="${2:-300}"
count="${3:-40}"
config="${4:-$root/config/7scenes.ini}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/seq/rgb" "$work/seq/depth"
cp "$src"/*.txt "$work/seq/"
i=0
while read -r t rgb td depth; do
    [[ "$t" == \#* ]] && continue
    if [ "$i" -ge "$first" ] && [ "$i" -lt $((first + count)) ]; then
        /usr/bin/python3 - "$work/seq/$rgb" "$work/seq/$depth" <<'PY'
# Black 640x480 colour (PNG content; readers go by content, not extension) and zero depth.
import struct, sys, zlib
def png(path, w, h, bitdepth, colourtype, bytes_per_px):
    raw = b"".join(b"\0" + bytes(w * bytes_per_px) for _ in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", w, h, bitdepth, colourtype, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                           chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
png(sys.argv[1], 640, 480, 8, 2, 3)
png(sys.argv[2], 640, 480, 16, 0, 2)
PY
    else
        ln -s "$src/$rgb" "$work/seq/$rgb"
        ln -s "$src/$depth" "$work/seq/$depth"
    fi
    i=$((i + 1))
done < "$src/associations.txt"
"$root/build/bin/semantic-mapper" "$work/seq" --config "$config" --out "$work/out" --quiet \
    --set segmentation.backend=none --set output.snapshots=false --set output.annotated_rawlog=false "${@:5}"
awk -F, -v a="$first" -v n="$count" 'NR > 1 && $1 >= a - 2 && $1 < a + n + 40 { print $1, $9, $11 }' \
    "$work/out/frames.csv" | awk '{ if ($2 != prev) { print "frame " $1 ": " $2 " (inliers " $3 ")"; prev = $2 } }'
/usr/bin/python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['tracking']; print('frames with pose %d, lost %d, relocalisations %d' % (t['frames_with_pose'], t['frames_lost'], t['relocalisations']))" "$work/out/metrics.json"
# Against every reference the folder has (7-Scenes: groundtruth_sfm.txt first, then
# KinectFusion's groundtruth.txt).
for gt in "$src"/groundtruth_*.txt "$src/groundtruth.txt"; do
    [ -f "$gt" ] || continue
    echo "ATE RMSE against $(basename "$gt"): $("$root/build/bin/smap-eval" ate "$gt" "$work/out/trajectory.txt" | awk '/rmse/ {print $2}') m"
done
