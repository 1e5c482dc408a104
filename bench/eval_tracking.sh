#!/usr/bin/env bash
# Tracking accuracy table (issue: ORB-SLAM-style tracking). Renders the synthetic presets
# (cached under $SMAP_EVAL_CACHE, default /tmp/smap-eval-cache), runs semantic-mapper on each
# and on ../shared/data/7scenes-redkitchen, and prints ATE RMSE / frames tracked per sequence.
# Optional: SMAP_OPEN3D=1 also runs Open3D's RGB-D odometry on 7-Scenes (python3-open3d);
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
seven="$root/../shared/data/7scenes-redkitchen"
if [ -d "$seven" ]; then
    run_one 7scenes-redkitchen "$seven" "$seven/groundtruth.txt" --config "$root/config/7scenes.ini" "$@"
    if [ "${SMAP_OPEN3D:-0}" = 1 ]; then
        /usr/bin/python3 "$root/bench/open3d_rgbd_odometry.py" "$seven" "$cache/open3d-7scenes.txt"
        echo -n "open3d-7scenes ATE: "
        "$bin/smap-eval" ate "$seven/groundtruth.txt" "$cache/open3d-7scenes.txt" | sed -n 2p
    fi
fi
