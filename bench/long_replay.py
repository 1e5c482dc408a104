#!/usr/bin/python3
"""A long recording that keeps revisiting one room: a TUM folder played forward, backward,
forward ... (PASSES passes, continuous motion, fresh 30 Hz timestamps, the reference poses
carried along; every pass after the first starts at the frame after the turn, so the motion
never stops). semantic-mapper runs on it and on one pass, each under /usr/bin/time -v, and the
script prints what a long recording asks of the mapper:

  keyframes               live keyframes at the end (metrics.json), and the ratio to one pass
  tracking cost           median tracking ms per frame over frames 1000-1999 and over the
                          last 1000, and their ratio: wall time (frames.csv tracking_ms),
                          the tracking thread's CPU time (tracking_cpu_ms: the work itself,
                          without the time another thread held the core) and the wait for the
                          map mutex (map_wait_ms); the wall time of a two-core machine also
                          holds the time local mapping, loop closing and segmentation took the
                          core from tracking
  peak memory             maximum resident set size
  ATE                     RMSE against each reference of the folder (groundtruth_sfm.txt first)
  loop closures           metrics.json's loop.closures (0 when the build has none)

Usage: bench/long_replay.py [BUILD_DIR] [--data DIR] [--config FILE] [--passes N]
                            [--keep DIR] [-- extra semantic-mapper args]
Defaults: build, ../shared/data/7scenes-redkitchen, config/7scenes.ini, 10.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from input_variants import list_variant, read_pairs, references  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def pass_order(n, passes):
    """Frame indices of `passes` alternating passes over n frames, the turning frame once."""
    order = list(range(n))
    for p in range(1, passes):
        step = list(range(n - 2, -1, -1)) if p % 2 else list(range(1, n))
        order += step
    return order


def run(build, data, config, out, extra):
    """Runs semantic-mapper under /usr/bin/time -v; returns the peak RSS in MiB."""
    cmd = ["/usr/bin/time", "-v", os.path.join(build, "bin", "semantic-mapper"), data,
           "--config", config, "--out", out, "--quiet", "--set", "output.snapshots=false",
           "--set", "output.annotated_rawlog=false"] + list(extra)
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit("semantic-mapper failed on %s:\n%s" % (data, done.stderr[-3000:]))
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)
    return int(peak.group(1)) / 1024.0 if peak else float("nan")


TIMING_COLUMNS = ("tracking_ms", "tracking_cpu_ms", "map_wait_ms")


def frame_timings(out):
    """frames.csv read once: per timing column, its values in frame order. tracking_ms is the
    wall time of tracking (matching, pose optimisation and the wait for the map mutex),
    tracking_cpu_ms the tracking thread's CPU time over it, map_wait_ms the wait. A column an
    older build does not write is left out."""
    with open(os.path.join(out, "frames.csv")) as f:
        header = f.readline().strip().split(",")
        col = {name: k for k, name in enumerate(header)}
        timings = {c: [] for c in TIMING_COLUMNS if c in col}
        frames = 0
        for line in f:
            r = line.rstrip("\n").split(",")
            frames += 1
            for c, values in timings.items():
                values.append(float(r[col[c]] or 0))
    return frames, timings


def print_cost_ratio(timings):
    """Medians of the timing columns over frames 1000-1999 and the last 1000, their ratios,
    and the waits for the map mutex over the whole run."""
    for column, what in (("tracking_ms", "tracking ms per frame (median, wall)"),
                         ("tracking_cpu_ms", "tracking CPU ms per frame (median)"),
                         ("map_wait_ms", "map mutex wait ms per frame (mean)")):
        costs = timings.get(column, [])
        if len(costs) < 3000:
            continue
        pick = statistics.mean if column == "map_wait_ms" else statistics.median
        a, b = pick(costs[1000:2000]), pick(costs[-1000:])
        print("  %s: frames 1000-1999 %.2f, last 1000 %.2f, ratio %.2f"
              % (what, a, b, b / a if a > 0 else float("nan")))
    waits = timings.get("map_wait_ms", [])
    if waits:
        print("  map mutex waits: %.1f s in total, %d over 20 ms, %d over 100 ms, longest %.0f ms"
              % (sum(waits) / 1000.0, sum(w > 20 for w in waits), sum(w > 100 for w in waits),
                 max(waits)))


def ate(build, data, out):
    rows = []
    for name in references(data):
        text = subprocess.run([os.path.join(build, "bin", "smap-eval"), "ate",
                               os.path.join(data, name), os.path.join(out, "trajectory.txt")],
                              capture_output=True, text=True).stdout
        m = re.search(r"rmse\S*\s+([0-9.]+)", text)
        rows.append((name, float(m.group(1)) if m else float("nan")))
    return rows


def report(label, build, data, out, peak):
    metrics = json.load(open(os.path.join(out, "metrics.json")))
    tracking = metrics["tracking"]
    loop = metrics.get("loop", {})
    frames, timings = frame_timings(out)
    print("%s: %d frames, %d with a pose, %d keyframes (%d culled), %d map points, peak %.0f MiB"
          % (label, frames, tracking["frames_with_pose"], tracking["keyframes"],
             tracking["keyframes_culled"], tracking["map_points"], peak))
    print("  ATE RMSE %s" % ", ".join("%.1f mm vs %s" % (1000 * r, g)
                                      for g, r in ate(build, data, out)))
    if loop:
        print("  loop closures %d, consistent revisits %d, correction ms median %.1f max %.1f"
              % (loop.get("closures", 0), loop.get("consistent_revisits", 0),
                 loop.get("correction_median_ms", 0.0), loop.get("correction_max_ms", 0.0)))
    print_cost_ratio(timings)
    return tracking["keyframes"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data",
                                                   "7scenes-redkitchen"))
    ap.add_argument("--config", default=os.path.join(ROOT, "config", "7scenes.ini"))
    ap.add_argument("--passes", type=int, default=10)
    ap.add_argument("--keep", help="write the outputs here instead of a temporary folder")
    # Everything after "--" goes to semantic-mapper (argparse's REMAINDER after an optional
    # positional would swallow the options too).
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    a = ap.parse_args(argv[:cut])
    extra = argv[cut + 1:]
    data = os.path.abspath(a.data)
    if not os.path.isdir(data):
        sys.exit("long_replay.py: %s not found" % data)
    with tempfile.TemporaryDirectory() as tmp:
        work = a.keep or tmp
        os.makedirs(work, exist_ok=True)
        n = len(read_pairs(data))
        seq = os.path.join(work, "passes-%d" % a.passes)
        if not os.path.exists(os.path.join(seq, "rgb.txt")):
            list_variant(data, seq, pass_order(n, a.passes), True)
        one = report("one pass", a.build, data, os.path.join(work, "out-one"),
                     run(a.build, data, a.config, os.path.join(work, "out-one"), extra))
        many = report("%d passes" % a.passes, a.build, seq, os.path.join(work, "out-passes"),
                      run(a.build, seq, a.config, os.path.join(work, "out-passes"), extra))
        print("keyframes: %d passes / one pass = %.2f" % (a.passes, many / max(one, 1)))


if __name__ == "__main__":
    main()
