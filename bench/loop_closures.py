#!/usr/bin/python3
"""Loop closing against ground truth. For each sequence, semantic-mapper runs in the default
configuration and (with --ablate) without the loop closer, without tracking's revisit joins
(the local map taking in old keyframes within [tracking] revisit_radius, a loop closure of small
drift), and without both; the script prints:

  frames with a pose, ATE RMSE against the sequence's reference (with --ablate, the ratios)
  loops          loops verified (metrics.json loop.list), and how many of them corrected the
                 map (the others were consistent revisits)
  false          verified loops whose measured relative pose (T_loop_keyframe) disagrees with
                 the reference's by more than 10 cm or 5 degrees
  revisit        the first frame that comes back within 0.5 m (and 30 degrees of view direction)
                 of a frame at least --gap frames older, and how many frames after it the first
                 loop was verified
  correction     median / max ms per correction (pose graph, points, fusion) and of the global
                 bundle adjustment after it

Sequences are given as NAME=FOLDER[,CONFIG][,REFERENCE]; CONFIG defaults to the folder's
camera.ini, REFERENCE to groundtruth_sfm.txt when the folder has one, else groundtruth.txt.
Usage: bench/loop_closures.py [--build DIR] [--ablate] [--gap N] NAME=FOLDER[,...]...
         [-- extra semantic-mapper args]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def quat_to_matrix(qx, qy, qz, qw):
    x, y, z, w = qx, qy, qz, qw
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose_matrix(v):
    """4x4 from tx ty tz qx qy qz qw."""
    T = np.eye(4)
    T[:3, :3] = quat_to_matrix(*v[3:7])
    T[:3, 3] = v[:3]
    return T


def read_tum(path):
    stamps, poses = [], []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                v = [float(x) for x in line.split()[:8]]
                stamps.append(v[0])
                poses.append(pose_matrix(v[1:]))
    return np.array(stamps), poses


def nearest(stamps, t):
    k = int(np.argmin(np.abs(stamps - t)))
    return k if abs(stamps[k] - t) < 0.02 else None


def rotation_deg(R):
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))


def revisit_frame(poses, gap):
    """First index that comes back within 0.5 m and 30 degrees of one `gap` or more older."""
    centres = np.array([T[:3, 3] for T in poses])
    views = np.array([T[:3, 2] for T in poses])
    for i in range(gap, len(poses)):
        old = slice(0, i - gap + 1)
        close = np.linalg.norm(centres[old] - centres[i], axis=1) < 0.5
        aligned = views[old] @ views[i] > np.cos(np.radians(30))
        if np.any(close & aligned):
            return i
    return None


def run(build, folder, config, out, extra):
    cmd = [os.path.join(build, "bin", "semantic-mapper"), folder, "--out", out, "--quiet",
           "--set", "output.snapshots=false", "--set", "output.annotated_rawlog=false"]
    if config:
        cmd += ["--config", config]
    done = subprocess.run(cmd + list(extra), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True)
    if done.returncode != 0:
        sys.exit("semantic-mapper failed on %s:\n%s" % (folder, done.stderr[-3000:]))
    return json.load(open(os.path.join(out, "metrics.json")))


def ate(build, reference, out):
    text = subprocess.run([os.path.join(build, "bin", "smap-eval"), "ate", reference,
                           os.path.join(out, "trajectory.txt")], capture_output=True,
                          text=True).stdout
    m = re.search(r"rmse\S*\s+([0-9.]+)", text)
    return float(m.group(1)) if m else float("nan")


def judge(closures, stamps, poses):
    """Count of closures whose relative pose disagrees with the reference."""
    false = 0
    for c in closures:
        a, b = nearest(stamps, c["loop_timestamp"]), nearest(stamps, c["timestamp"])
        if a is None or b is None:
            continue
        truth = np.linalg.inv(poses[a]) @ poses[b]
        est = pose_matrix(c["T_loop_keyframe"])
        err = np.linalg.inv(truth) @ est
        if np.linalg.norm(err[:3, 3]) > 0.10 or rotation_deg(err[:3, :3]) > 5.0:
            false += 1
    return false


def parse_sequence(spec):
    name, _, rest = spec.partition("=")
    parts = rest.split(",")
    folder = parts[0]
    config = parts[1] if len(parts) > 1 and parts[1] else None
    if config is None and os.path.exists(os.path.join(folder, "camera.ini")):
        config = os.path.join(folder, "camera.ini")
    reference = parts[2] if len(parts) > 2 else None
    if reference is None:
        sfm = os.path.join(folder, "groundtruth_sfm.txt")
        reference = sfm if os.path.exists(sfm) else os.path.join(folder, "groundtruth.txt")
    return name, folder, config, reference


def summary(build, name, folder, config, reference, out, extra, gap):
    metrics = run(build, folder, config, out, extra)
    loop = metrics.get("loop", {})
    found = loop.get("list", [])
    closures = [c for c in found if c.get("corrected", True)]
    stamps, poses = read_tum(reference)
    rmse = ate(build, reference, out)
    line = ("%-24s %5d/%-5d posed, ATE %6.1f mm, %d loops verified (%d false), %d corrected" %
            (name, metrics["tracking"]["frames_with_pose"], metrics["frames"], 1000 * rmse,
             len(found), judge(found, stamps, poses), len(closures)))
    revisit = revisit_frame(poses, gap)
    if revisit is not None:
        first = min((c["frame"] for c in found), default=None)
        line += ", revisit at frame %d, first loop %s" % (
            revisit, "at frame %d (%+d)" % (first, first - revisit) if first is not None
            else "none")
    if closures:
        line += ", correction ms median %.1f max %.1f, BA after it median %.0f" % (
            float(np.median([c["correction_ms"] for c in closures])),
            max(c["correction_ms"] for c in closures),
            float(np.median([c["global_ba_ms"] for c in closures])))
    print(line, flush=True)
    return rmse


# The ablations: tracking's own revisit joins (keyframes within [tracking] revisit_radius join
# the local map, so a small drift closes itself in local BA) are a loop closure too, so the
# baseline without any loop closure switches both off.
ABLATIONS = [
    ("no loop closer", ["--set", "loop_closing.enabled=false"]),
    ("loop closer, no revisit joins", ["--set", "tracking.revisit_radius=0"]),
    ("no loop closure at all", ["--set", "loop_closing.enabled=false",
                                "--set", "tracking.revisit_radius=0"]),
]


def ablate(a, name, folder, config, reference, tmp, extra, on):
    """Runs the ablations and prints the ATE ratios against the one without any loop closure."""
    rmse = {}
    for k, (label, args) in enumerate(ABLATIONS):
        rmse[label] = summary(a.build, "%s (%s)" % (name, label), folder, config, reference,
                              os.path.join(tmp, "%s-ablation%d" % (name, k)), extra + args, a.gap)
    none = rmse["no loop closure at all"]
    print("%-24s ATE ratios: default / no loop closer = %.2f; default / none at all = %.2f; "
          "loop closer alone / none at all = %.2f" % (
              name, on / rmse["no loop closer"], on / none,
              rmse["loop closer, no revisit joins"] / none), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--ablate", action="store_true",
                    help="also run without the loop closer, without revisit joins and without both")
    ap.add_argument("--gap", type=int, default=300)
    ap.add_argument("sequences", nargs="+")
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    a = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    with tempfile.TemporaryDirectory() as tmp:
        for spec in a.sequences:
            name, folder, config, reference = parse_sequence(spec)
            on = summary(a.build, name, folder, config, reference, os.path.join(tmp, name),
                         extra, a.gap)
            if a.ablate:
                ablate(a, name, folder, config, reference, tmp, extra, on)

if __name__ == "__main__":
    main()
