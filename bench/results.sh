#!/usr/bin/env bash
# docs/results.md in one run: the paper's Table II (ATE RMSE per sequence, dynamic filter off /
# paper mode / best mode), its Table III (frame-level scores of the keyframes' person
# segmentation and of Algorithm 1's dynamic mask against ground truth), and the end-to-end speed
# and peak memory of semantic-mapper on 7-Scenes (1000 frames, 640x480, ESPNetv2 + CRF on every
# keyframe; median of 3 runs, /usr/bin/time -v), OpenCV's RGB-D odometry on the same frames
# (bench/peer_rgbd_odometry), and the kinds of human motion composited into 7-Scenes
# (bench/people_scenarios.sh: tracking and people left in the maps), at 30 frames/s and at 15
# (every other frame).
# Sequences: synthetic presets (smap-synth, 300 frames), 7-Scenes (static, real) and 7-Scenes
# with composited people (real frames, real person cut-outs), all generated into the cache
# ($SMAP_EVAL_CACHE, default /tmp/smap-eval-cache) when missing. About 45 minutes on 2 cores.
# Usage: bench/results.sh [BUILD_DIR]   (writes $SMAP_RESULTS_OUT, default docs/results.md)
#        SMAP_RESULTS_REPORT_ONLY=1 bench/results.sh   rewrites the page from the last runs' files
#        SMAP_RESULTS_SPEED_ONLY=1 bench/results.sh    re-measures only the speed (e.g. with
#        SMAP_RESULTS_SPEED_RUNS=5 on a busy machine), keeping the last Table II / III runs
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
bin="$build/bin"
cache="${SMAP_EVAL_CACHE:-/tmp/smap-eval-cache}"
shared="$root/../shared"
presets="${SMAP_RESULTS_PRESETS:-walking_xyz walking_halfsphere walking_rpy sitting_xyz}"
out_md="${SMAP_RESULTS_OUT:-$root/docs/results.md}"
speed_runs="${SMAP_RESULTS_SPEED_RUNS:-3}"
# the kinds of human motion (bench/people_scenarios.sh; its map_ghosts.py needs python3-open3d and
# python3-opencv)
scenarios="${SMAP_RESULTS_SCENARIOS:-crossing:300 crowd:234 seated:500 stop_and_stay:450}"
mkdir -p "$cache"
seven="$shared/data/7scenes-redkitchen"
model="$root/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx"  # the shipped model, the default
[ -f "$model" ] || { echo "results.sh: the ESPNetv2 model is missing: $model" >&2; exit 2; }

list="$cache/results-runs.txt"
speed="$cache/results-speed.txt"
commit_file="$cache/results-commit.txt"
peers="$cache/results-peers.txt"
scen30="$cache/results-scenarios-30.md"
scen15="$cache/results-scenarios-15.md"
if [ "${SMAP_RESULTS_REPORT_ONLY:-0}" != 1 ]; then
if [ "${SMAP_RESULTS_SPEED_ONLY:-0}" != 1 ]; then
: >"$list"
(cd "$root" && git rev-parse --short HEAD) >"$commit_file"
# one SEQUENCE MODE INPUT CAMERA_CONFIG [args...]: runs semantic-mapper, records its metrics.json
one() {
    local seq="$1" mode="$2" input="$3" camera="$4"
    shift 4
    local out="$cache/res-$seq-$mode" modecfg=()
    case "$mode" in
        off) modecfg=(--config "$root/config/modes/best.ini" --set dynamic.mode=off) ;;
        paper) modecfg=(--config "$root/config/modes/paper.ini") ;;
        best) modecfg=(--config "$root/config/modes/best.ini") ;;
    esac
    echo "  $seq / $mode" >&2
    "$bin/semantic-mapper" "$input" --config "$camera" "${modecfg[@]}" --out "$out" --quiet \
        --set output.annotated_rawlog=false --set output.snapshots=false "$@" >/dev/null
    echo "$seq $mode $out/metrics.json" >>"$list"
}

echo "Table II / III runs:" >&2
for p in $presets; do
    dir="$cache/$p-300"
    [ -f "$dir/groundtruth.txt" ] ||
        "$bin/smap-synth" --preset "$p" --out "$dir" --frames 300 --no-rawlog >/dev/null
    for m in off paper best; do one "$p" "$m" "$dir" "$root/config/synthetic.ini"; done
done
if [ -d "$seven" ]; then
    # Both of 7-Scenes' references: the SfM one (colour camera) is the evaluation, KinectFusion's
    # groundtruth.txt (depth camera, 49 mm from it) is reported beside it.
    for m in off paper best; do
        one 7scenes "$m" "$seven" "$root/config/7scenes.ini" \
            --gt "$seven/groundtruth_sfm.txt" --gt "$seven/groundtruth.txt"
    done
    if [ -d "$shared/data/people" ]; then
        # Made in the colour camera's geometry: registered frames, people placed with the
        # colour camera's SfM poses (which are then the composite's ground truth).
        comp="$cache/7scenes-people-colour-1000"
        [ -f "$comp/groundtruth.txt" ] ||
            "$bin/smap-synth" --composite-onto "$seven" --people "$shared/data/people" \
                --config "$root/config/7scenes.ini" --ground-truth "$seven/groundtruth_sfm.txt" \
                --frames 1000 --people-count 4 --out "$comp" --no-rawlog >/dev/null
        # Composite labels: 15 on people, 255 ("not a person") elsewhere: nothing is void.
        for m in off paper best; do
            one 7scenes-people "$m" "$comp" "$comp/camera.ini" --gt-void none
        done
    fi
    : >"$peers"
    if [ -x "$bin/peer_rgbd_odometry" ] && [ -d "$seven" ]; then
        echo "Peer: OpenCV RgbdOdometry" >&2
        for seq in 7scenes 7scenes-people; do
            input="$seven" camera="$root/config/7scenes.ini" gt="$seven/groundtruth_sfm.txt"
            if [ "$seq" = 7scenes-people ]; then
                input="${comp:-}" camera="${comp:-}/camera.ini" gt="${comp:-}/groundtruth.txt"
            fi
            [ -d "$input" ] || continue
            "$bin/peer_rgbd_odometry" "$input" "$cache/peer-opencv-$seq.txt" \
                --config "$camera" >/dev/null
            rmse=$("$bin/smap-eval" ate "$gt" "$cache/peer-opencv-$seq.txt" |
                awk '/rmse/ {print $2; exit}')
            echo "$seq OpenCV-RgbdOdometry $rmse" >>"$peers"
        done
    fi
    if [ -d "$shared/data/people" ]; then
        echo "Kinds of human motion, 30 frames/s:" >&2
        SMAP_SCENARIOS="$scenarios" SMAP_PRESETS="" SMAP_RUNS=default \
            bash "$root/bench/people_scenarios.sh" "$build" >"$scen30"
        echo "Kinds of human motion, 15 frames/s:" >&2
        SMAP_SCENARIOS="$scenarios" SMAP_PRESETS="" SMAP_RUNS=default \
            bash "$root/bench/people_scenarios.sh" "$build" --set input.stride=2 >"$scen15"
    fi
fi
else
    [ -s "$list" ] || { echo "results.sh: no earlier Table II / III runs in $list" >&2; exit 2; }
    (cd "$root" && git rev-parse --short HEAD) | cmp -s - "$commit_file" ||
        echo "results.sh: the Table II / III runs are from commit $(cat "$commit_file")" >&2
fi

echo "End-to-end speed on 7-Scenes ($speed_runs runs):" >&2
: >"$speed"
if [ -d "$seven" ]; then
    for r in $(seq 1 "$speed_runs"); do
        out="$cache/res-speed-$r"
        /usr/bin/time -v "$bin/semantic-mapper" "$seven" --config "$root/config/7scenes.ini" \
            --gt "$seven/groundtruth_sfm.txt" --gt "$seven/groundtruth.txt" \
            --out "$out" --quiet >/dev/null 2>"$out.time"
        rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out.time")
        echo "$out/metrics.json $rss" >>"$speed"
        echo "  run $r: $(grep -o '"frames_per_second": [0-9.]*' "$out/metrics.json" | head -1), peak RSS $rss kB" >&2
    done
fi
fi

/usr/bin/python3 - "$list" "$speed" "$out_md" "$(cat "$commit_file")" "$peers" "$scen30" "$scen15" <<'PY'
import json, sys, statistics, datetime, os
runs_file, speed_file, out_md, commit, peers_file, scen30_file, scen15_file = sys.argv[1:8]
runs = {}
for line in open(runs_file):
    seq, mode, path = line.split()
    runs.setdefault(seq, {})[mode] = dict(json.load(open(path)), _dir=os.path.dirname(path))

def lost_stretches(run_dir):
    """'first-last' frame index ranges without a pose in the run's frames.csv (status lost or
    not_initialised)."""
    import csv
    spans, start, prev = [], None, None
    with open(os.path.join(run_dir, "frames.csv")) as f:
        for row in csv.DictReader(f):
            i = int(row["index"])
            if row["status"] in ("lost", "not_initialised"):
                if start is None:
                    start = i
                prev = i
            elif start is not None:
                spans.append((start, prev))
                start = None
    if start is not None:
        spans.append((start, prev))
    return ["%d" % a if a == b else "%d-%d" % (a, b) for a, b in spans]

def ate(m):
    e = m.get("evaluation", {}).get("ate")
    return e["rmse"] if e else float("nan")

def other_ates(m):
    """[(reference file name, ATE RMSE)] of the further references in metrics.json."""
    out = []
    for r in m.get("other_references", []):
        if "ate" in r:
            out.append((os.path.basename(r["ground_truth"]), r["ate"]["rmse"]))
    return out

L = []
L.append("# Results")
L.append("")
L.append("Produced by `bench/results.sh` (commit %s, %s) on the project's 2-core Debian 12 machine;"
         % (commit, datetime.date.today().isoformat()))
L.append("every figure below comes from the `metrics.json` of a semantic-mapper run. Modes: *off* = the")
L.append("best configuration with the dynamic filter off (ORB-SLAM2-like tracking), *paper* =")
L.append("`config/modes/paper.ini` (the paper's method and parameters), *best* = `config/modes/best.ini`")
L.append("(the defaults). Sequences: synthetic smap-synth presets (300 frames, people walking or")
L.append("sitting, exact ground truth), 7-Scenes red kitchen (1000 real Kinect frames, static) and the")
L.append("same frames with 4 real person cut-outs composited walking through them (docs/synthetic.md).")
L.append("")
L.append("## Table II: absolute trajectory error")
L.append("")
L.append("ATE RMSE (m) after SE(3) alignment, every frame; improvement = (off - mode) / off.")
L.append("7-Scenes against its SfM reference (groundtruth_sfm.txt, the colour camera's poses), its")
L.append("KinectFusion reference below; the composites' ground truth is the SfM poses they were made with.")
L.append("")
L.append("| sequence | frames | off | paper | best | paper vs off | best vs off | frames with a pose (off / paper / best) | keyframes (best) |")
L.append("|---|---|---|---|---|---|---|---|---|")
for seq, modes in runs.items():
    off, paper, best = (ate(modes[k]) if k in modes else float("nan") for k in ("off", "paper", "best"))
    imp = lambda x: "%+.0f%%" % (100.0 * (off - x) / off) if off == off and off > 0 else "-"
    b = modes.get("best", {})
    posed = " / ".join(str(modes[k]["tracking"]["frames_with_pose"]) if k in modes else "-"
                       for k in ("off", "paper", "best"))
    L.append("| %s | %d | %.4f | %.4f | %.4f | %s | %s | %s | %d |" % (
        seq, b.get("frames", 0), off, paper, best, imp(paper), imp(best), posed,
        b.get("keyframes", {}).get("submitted", 0)))
others = [(seq, k, other_ates(modes[k])) for seq, modes in runs.items()
          for k in ("off", "paper", "best") if k in modes and other_ates(modes[k])]
if others:
    L.append("")
    L.append("The same runs against their further references (7-Scenes: KinectFusion's groundtruth.txt,")
    L.append("the depth camera's poses, 49 mm ATE RMSE from the SfM reference; docs/tracking.md):")
    L.append("")
    L.append("| sequence | mode | reference | ATE RMSE (m) |")
    L.append("|---|---|---|---|")
    for seq, k, refs in others:
        for name, v in refs:
            L.append("| %s | %s | %s | %.4f |" % (seq, k, name, v))
L.append("")
L.append("## Table III: keyframe segmentation against ground truth")
L.append("")
L.append("Frame-level scores over the keyframes (docs/method.md section 5): per keyframe, a class present in")
L.append("the ground truth and segmented with IoU >= 0.5 is a TP, present but missed a FN, absent but")
L.append("predicted a FP, absent and not predicted a TN. *person* is the CNN + CRF segmentation")
L.append("(ESPNetv2 at 320x240 + dense CRF); *dynamic mask* is Algorithm 1's M (pixels removed from the")
L.append("map) against the moving pixels. Best mode.")
L.append("")
L.append("| sequence | what | keyframes | TP / FN / FP / TN | FPR | FNR | Re | Pr | PWC | IoU |")
L.append("|---|---|---|---|---|---|---|---|---|---|")
def fmt(v):
    return "-" if v is None else "%.3f" % v
for seq, modes in runs.items():
    m = modes.get("best")
    if not m or "segmentation_scores" not in m:
        continue
    s = m["segmentation_scores"]
    rows = []
    seg = s.get("segmentation")
    if seg:
        rows += [("person", seg["frames"], c) for c in seg["classes"] if c["name"] == "person"]
    dm = s.get("dynamic_mask")
    if dm:
        rows += [("dynamic mask", dm["frames"], dm["classes"][0])]
    for what, n, c in rows:
        L.append("| %s | %s | %d | %d / %d / %d / %d | %s | %s | %s | %s | %s | %s |" % (
            seq, what, n, c["tp"], c["fn"], c["fp"], c["tn"], fmt(c["fpr"]), fmt(c["fnr"]),
            fmt(c["recall"]), fmt(c["precision"]), fmt(c["pwc"]), fmt(c["iou"])))
L.append("")
speed = [l.split() for l in open(speed_file) if l.strip()]
if speed:
    ms = [(json.load(open(p)), int(rss)) for p, rss in speed]
    fps = [m["timings"]["frames_per_second"] for m, _ in ms]
    med = sorted(ms, key=lambda x: x[0]["timings"]["frames_per_second"])[len(ms) // 2]
    m, rss = med
    t = m["timings"]
    L.append("## End-to-end speed and memory")
    L.append("")
    L.append("`semantic-mapper ../shared/data/7scenes-redkitchen --config config/7scenes.ini` (defaults =")
    L.append("best mode: every output on, ESPNetv2 320x240 + CRF on every keyframe), %d runs:" % len(ms))
    L.append("")
    L.append("- frames/s over the whole run (setup, %d frames, finishing the queue, every output file): %s;"
             % (m["frames"], ", ".join("%.1f" % f for f in fps)))
    L.append("  **median %.1f**." % statistics.median(fps))
    L.append("- peak memory (`/usr/bin/time -v` maximum RSS): %s MiB; **max %.0f MiB**."
             % (", ".join("%.0f" % (int(r) / 1024) for _, r in ms), max(int(r) for _, r in ms) / 1024))
    L.append("- ATE RMSE %.4f m against groundtruth_sfm.txt (%s), %d keyframes segmented and mapped,"
             % (ate(m), ", ".join("%.4f m against %s" % (v, n) for n, v in other_ates(m)) or "-",
                m["keyframes"]["mapped"]))
    L.append("  %d map points, %d octomap voxels."
             % (m["map"]["points"], m["map"]["octomap_occupied_voxels"]))
    L.append("")
    L.append("Breakdown of the median run. Five threads share the 2 cores (reading, front end, tracking")
    L.append("with local mapping, keyframe worker, and OpenCV's helpers), so per-stage wall times overlap and")
    L.append("include waiting for a core:")
    L.append("")
    L.append("| stage | thread | median per item (ms) | total (s) | items |")
    L.append("|---|---|---|---|---|")
    for key, thread in [("read_decode", "reader"), ("feature_extraction", "front end"),
                        ("dynamic_filter", "front end"), ("tracking", "tracking"),
                        ("segmentation", "keyframe worker"), ("association", "keyframe worker"),
                        ("map_insertion", "keyframe worker"), ("keyframe_outputs", "keyframe worker"),
                        ("keyframe_queue_wait", "tracking")]:
        v = t[key]
        L.append("| %s | %s | %.1f | %.2f | %d |" % (key.replace("_", " "), thread, v["median_ms"], v["total_s"], v["count"]))
    L.append("| local mapping (local BA %.2f s) | tracking | | %.2f | %d keyframes |" % (
        t["local_ba_s"], t["local_mapping_total_s"], m["keyframes"]["submitted"]))
    L.append("| finishing (queue, re-anchoring) | main | | %.2f | |" % t["finish_s"])
    L.append("| writing outputs | main | | %.2f | |" % t["outputs_s"])
    L.append("| **whole run** | | | **%.2f** | %d frames |" % (t["total_s"], m["frames"]))
    L.append("")
def read(path):
    return open(path).read().strip() if os.path.exists(path) and os.path.getsize(path) else ""
peers = [l.split() for l in open(peers_file) if l.strip()] if os.path.exists(peers_file) else []
if peers:
    L.append("## Peers on the same frames")
    L.append("")
    L.append("ATE RMSE (m) of OpenCV's RGB-D odometry (opencv_contrib `cv::rgbd::RgbdOdometry`, frame to")
    L.append("frame, `bench/peer_rgbd_odometry`) on the frames semantic-mapper reads, beside the best mode's:")
    L.append("")
    L.append("| sequence | OpenCV RgbdOdometry | semantic-mapper (best) |")
    L.append("|---|---|---|")
    for seq, name, v in peers:
        ours = ate(runs[seq]["best"]) if seq in runs and "best" in runs[seq] else float("nan")
        L.append("| %s | %.4f | %.4f |" % (seq, float(v), ours))
    L.append("")
scen30, scen15 = read(scen30_file), read(scen15_file)
if scen30:
    L.append("## Table II: kinds of human motion")
    L.append("")
    L.append("`SMAP_PRESETS= SMAP_RUNS=default bench/people_scenarios.sh build`: people composited into the")
    L.append("7-Scenes frames as they cross, crowd, sit, and stop and stay (docs/synthetic.md), each against")
    L.append("the same frames without people, in the default mode (the paper's mode is in Table II above;")
    L.append("`SMAP_RUNS` adds the other modes). People left in")
    L.append("the maps: points (voxels) of the run with people that the run without people does not have,")
    L.append("as a share of the map, and of those the ones where a person was (bench/map_ghosts.py).")
    L.append("")
    L.append(scen30)
    L.append("")
if scen15:
    L.append("## The same at 15 frames/s")
    L.append("")
    L.append("`SMAP_PRESETS= SMAP_RUNS=default bench/people_scenarios.sh build --set input.stride=2`: every")
    L.append("other frame of the same composites, default mode. Parameters that mean time are in seconds")
    L.append("(docs/method.md), so the keyframe spacing, the filter's baseline and the map's confirmation")
    L.append("span stay what they are at 30 frames/s.")
    L.append("")
    L.append(scen15)
    L.append("")
L.append("## Reading the tables")
L.append("")
L.append("- ATE is computed over the frames with a pose; compare it with the frames-with-a-pose column.")
gaps = []
for seq, modes in runs.items():
    for mode in ("off", "paper", "best"):
        if mode in modes:
            s = lost_stretches(modes[mode]["_dir"])
            if s:
                gaps.append("%s %s: %s" % (seq, mode, ", ".join(s)))
if gaps:
    L.append("  Frames without a pose (`lost` or `not_initialised` in frames.csv; left out of the ATE): "
             + "; ".join(gaps) + ".")
else:
    L.append("  No run has a frame `lost` or `not_initialised`: every frame has a pose in every run.")
L.append("- The dynamic mask scored is the one the map uses: Algorithm 1's M grown along the depth")
L.append("  (`[association] grow_pixels`, docs/mapping.md). Growing covers more of each person, and")
L.append("  some background beside them, which the IoU counts against it.")
L.append("- The runs use the default, real-time mode: two runs of the same sequence can differ a little")
L.append("  (docs/pipeline.md, \"Real-time and reproducible runs\"); the timings vary with the machine's load.")
L.append("")
tmp = out_md + ".tmp"
open(tmp, "w").write("\n".join(L))
os.replace(tmp, out_md)
print("wrote", out_md)
PY
