#!/usr/bin/env bash
# Tracking accuracy table (ORB-SLAM-style tracking). Renders the synthetic presets
# (cached under $SMAP_EVAL_CACHE, default /tmp/smap-eval-cache), runs semantic-mapper on each
# and on ../shared/data/7scenes-redkitchen, and prints ATE RMSE / frames tracked per sequence.
# Optional: SMAP_PEERS=1 also runs the peers on 7-Scenes: OpenCV's RgbdOdometry
# (build/bin/peer_rgbd_odometry) and Open3D's RGB-D odometry (python3-open3d), scored against
# both 7-Scenes references as ours is;
# SMAP_EVAL_SEEDS="1 2 3" renders each preset with those smap-synth seeds (other scenes,
# people and camera paths; default 1), rows named PRESET-sSEED for seeds other than 1.
# Usage: bench/eval_tracking.sh [BUILD_DIR] [extra semantic-mapper args...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
bin="$build/bin"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
frames="${SMAP_EVAL_FRAMES:-300}"
seeds="${SMAP_EVAL_SEEDS:-1}"
presets="${SMAP_EVAL_PRESETS:-static_xyz static_halfsphere static_rpy static_static static_handheld walking_xyz walking_halfsphere walking_rpy walking_static sitting_xyz sitting_halfsphere}"
mkdir -p "$cache"

printf '%-22s %8s %10s %10s %10s %9s\n' sequence frames tracked "ATE_rmse_m" "ATE_mean_m" fps
run_one() {
    local name="$1" input="$2" gt="$3"
    shift 3
    local out="$cache/out-$name"
    # tracking alone: no keyframe segmentation or map outputs
    "$bin/semantic-mapper" "$input" --out "$out" --quiet --set segmentation.backend=none \
        --set output.snapshots=false --set output.annotated_rawlog=false "$@" >/dev/null
    local json="$out/ate.json"
    "$bin/smap-eval" ate "$gt" "$out/trajectory.txt" --json "$json" >/dev/null
    /usr/bin/python3 - "$name" "$out/metrics.json" "$json" <<'PY'
import json, sys
name, summary, ate = sys.argv[1:4]
s = json.load(open(summary)); a = json.load(open(ate))
print("%-22s %8d %10d %10.4f %10.4f %9.1f" % (name, s["frames"], s["tracking"]["frames_with_pose"],
      a["rmse"], a["mean"], s["timings"]["frames_per_second"]))
PY
}

for p in $presets; do
    for seed in $seeds; do
        name="$p" dir="$cache/$p-$frames"
        if [ "$seed" != 1 ]; then
            name="$p-s$seed" dir="$cache/$p-$frames-s$seed"
        fi
        if [ ! -f "$dir/groundtruth.txt" ]; then
            "$bin/smap-synth" --preset "$p" --seed "$seed" --out "$dir" --frames "$frames" \
                --no-rawlog >/dev/null
        fi
        run_one "$name" "$dir" "$dir/groundtruth.txt" --config "$root/config/synthetic.ini" "$@"
    done
done
# 7-Scenes against both of its references: the SfM one (groundtruth_sfm.txt, the colour
# camera's poses) is the row, KinectFusion's (groundtruth.txt, the depth camera's) follows.
both_references() {  # NAME TRAJECTORY
    for ref in groundtruth_sfm groundtruth; do
        printf '  %-28s ATE RMSE vs %-16s %s m\n' "$1" "$ref.txt" \
            "$("$bin/smap-eval" ate "$seven/$ref.txt" "$2" | awk '/rmse/ {print $2}')"
    done
}
seven="$root/../shared/data/7scenes-redkitchen"
if [ -d "$seven" ]; then
    run_one 7scenes-redkitchen "$seven" "$seven/groundtruth_sfm.txt" --config "$root/config/7scenes.ini" "$@"
    both_references "ours" "$cache/out-7scenes-redkitchen/trajectory.txt"
    # Peers on the same input (SMAP_PEERS=1): OpenCV's RgbdOdometry reads the frames through our
    # FrameSource (registered as ours are) and exports them; Open3D reads that export.
    if [ "${SMAP_PEERS:-${SMAP_OPEN3D:-0}}" = 1 ]; then
        registered="$cache/7scenes-as-read"
        rm -rf "$registered"
        "$bin/peer_rgbd_odometry" "$seven" "$cache/opencv-7scenes.txt" \
            --config "$root/config/7scenes.ini" --export "$registered" >/dev/null
        both_references "OpenCV RgbdOdometry" "$cache/opencv-7scenes.txt"
        /usr/bin/python3 "$root/bench/open3d_rgbd_odometry.py" "$registered" \
            "$cache/open3d-7scenes.txt" --fx 526.3 --fy 531.0 --cx 318.7 --cy 239.3 \
            --depth-factor 5000 >/dev/null
        both_references "Open3D RGB-D odometry" "$cache/open3d-7scenes.txt"
    fi
fi
