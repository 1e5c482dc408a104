#!/usr/bin/python3
"""Per-frame tracking cost and end-to-end frames/s of two or more builds, run alternately.

A cost bound compares builds: the tracking and dynamic filter of one frame against what an
earlier commit took, and end-to-end frames/s on 7-Scenes. Run both
builds one after the other, round after round, on the same machine (a shared machine drifts;
alternating spreads the drift over both), and compare medians.

Each VARIANT is LABEL=CHECKOUT[,EXTRA], a checkout (a git worktree of that commit) with its
semantic-mapper built in CHECKOUT/build/bin; EXTRA is a space-separated list of further
semantic-mapper arguments (e.g. "--set semantic_evidence.enabled=false"). semantic-mapper runs in
CHECKOUT, so relative paths (config/7scenes.ini, ../shared) are that checkout's.

Each SEQUENCE is NAME=INPUT[,CONFIG] (CONFIG relative to the checkout, or absolute; default:
INPUT/camera.ini when it exists). Per run it prints, from frames.csv: the median per frame of
extraction + tracking + dynamic filter + semantic evidence (the tracking thread's work for one
frame; tracking_ms includes the wait for the map mutex), the median of tracking + dynamic
filter + semantic evidence alone, and frames/s over the whole run (wall time from start to exit,
every output file written). Then, per sequence and variant, the medians over the runs and the
ratio to the first variant.

Usage:
  bench/tracking_cost_ab.py --variant base=/tmp/base --variant new=. \\
      --sequence 7scenes=../shared/data/7scenes-redkitchen,config/7scenes.ini [--runs 3]
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

STAGES = ("extraction_ms", "tracking_ms", "dynamic_filter_ms", "semantic_ms")


def parse_variant(text):
    label, _, rest = text.partition("=")
    checkout, _, extra = rest.partition(",")
    if not label or not checkout:
        sys.exit("--variant %r: expected LABEL=CHECKOUT[,EXTRA ARGS]" % text)
    binary = os.path.join(checkout, "build", "bin", "semantic-mapper")
    if not os.access(binary, os.X_OK):
        sys.exit("--variant %s: %s is not built (no executable %s)" % (label, checkout, binary))
    return label, os.path.abspath(checkout), extra.split()


def parse_sequence(text):
    name, _, rest = text.partition("=")
    data, _, config = rest.partition(",")
    if not name or not data:
        sys.exit("--sequence %r: expected NAME=INPUT[,CONFIG]" % text)
    if not config and os.path.isfile(os.path.join(data, "camera.ini")):
        config = os.path.join(os.path.abspath(data), "camera.ini")
    return name, data, config


def frame_costs(frames_csv):
    """Per posed or attempted frame: (all four stages, the three after extraction) in ms."""
    with open(frames_csv, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("tracking_ms")]
    if not rows:
        sys.exit("%s: no frame with a tracking_ms" % frames_csv)

    def total(row, stages):
        return sum(float(row[s]) for s in stages if row.get(s))

    return ([total(r, STAGES) for r in rows], [total(r, STAGES[1:]) for r in rows])


def run_once(variant, sequence, out_root):
    """One semantic-mapper run; returns (frames, median all stages, median without extraction,
    frames/s)."""
    label, checkout, extra = variant
    name, data, config = sequence
    out = os.path.join(out_root, "%s-%s" % (name, label))
    cmd = [os.path.join(checkout, "build", "bin", "semantic-mapper"), data, "--out", out,
           "--quiet", "--set", "output.snapshots=false", "--set", "output.annotated_rawlog=false"]
    if config:
        cmd[2:2] = ["--config", config]
    start = time.monotonic()
    done = subprocess.run(cmd + extra, cwd=checkout, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    wall = time.monotonic() - start
    if done.returncode != 0:
        sys.exit("%s on %s failed (exit %d): %s" % (label, name, done.returncode,
                                                    done.stderr.strip()[-500:]))
    every, after = frame_costs(os.path.join(out, "frames.csv"))
    return len(every), statistics.median(every), statistics.median(after), len(every) / wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variant", action="append", required=True, type=parse_variant)
    ap.add_argument("--sequence", action="append", required=True, type=parse_sequence)
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    if args.runs < 1:
        sys.exit("--runs %d: at least 1" % args.runs)
    results = {}
    with tempfile.TemporaryDirectory(prefix="smap-cost-ab.") as out_root:
        for round_ in range(1, args.runs + 1):
            for seq in args.sequence:
                for var in args.variant:
                    frames, every, after, fps = run_once(var, seq, out_root)
                    results.setdefault((seq[0], var[0]), []).append((every, after, fps))
                    print("round %d %-10s %-14s %4d frames  per frame %.2f ms (without extraction "
                          "%.2f ms)  %.1f frames/s" % (round_, seq[0], var[0], frames, every,
                                                       after, fps), flush=True)
    print("\nmedians over %d runs (ratio to %s)" % (args.runs, args.variant[0][0]))
    for seq in args.sequence:
        base = [statistics.median(x) for x in zip(*results[(seq[0], args.variant[0][0])])]
        for var in args.variant:
            med = [statistics.median(x) for x in zip(*results[(seq[0], var[0])])]
            print("%-10s %-14s per frame %.2f ms (%.2fx)  without extraction %.2f ms (%.2fx)  "
                  "%.1f frames/s (%.2fx)" % (seq[0], var[0], med[0], med[0] / base[0], med[1],
                                             med[1] / base[1], med[2], med[2] / base[2]))


if __name__ == "__main__":
    main()
