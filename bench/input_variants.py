#!/usr/bin/python3
"""Tracking on variants of one real TUM folder: the inputs a user may bring that the test data
does not show. For each variant, semantic-mapper runs deterministically (local mapping on the
tracking thread, segmentation off, default dynamic filter) and the script prints the frames
with a pose and the ATE against each of the variant's references (every groundtruth*.txt of the
folder: 7-Scenes' groundtruth_sfm.txt and groundtruth.txt). A [depth_camera] of the preset
(depth not registered to colour) is halved or cropped with the images as [camera] is.

  forward-backward  the frames played forward then backward (a TUM list over the same files,
                    absolute paths): the way back must track against the map of the way out
  first-N           the first N frames as they are (the twin of the next three)
  half-size         the first N frames at half the size (colour 2x2-averaged, depth
                    subsampled, both cameras' intrinsics halved)
  holes-65535       the first N frames with depth holes written as 65535 (the original
                    7-Scenes files' hole value) instead of 0: must equal first-N
  via-rawlog        holes-65535 converted by tum2rawlog and read back: must equal first-N
  crop-16x9         the first N frames cropped to 640x360 (principal point moved)
  stride-S          every S-th frame (input.stride)

Needs Open3D (Debian python3-open3d) for image reading and writing, and numpy.
Usage: bench/input_variants.py [BUILD_DIR] [--data DIR] [--config FILE] [--first N]
Defaults: build, ../shared/data/7scenes-redkitchen, config/7scenes.ini, 300.
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

try:
    import open3d as o3d
except ImportError:
    sys.exit("input_variants.py needs Open3D: apt-get install python3-open3d")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_list(path):
    """[[column, ...]] of a TUM list, comments skipped."""
    with open(path) as f:
        return [line.split() for line in f if line.strip() and not line.startswith("#")]


def read_pairs(data):
    """[(rgb time, rgb file, depth time, depth file)]: associations.txt, else rgb.txt and
    depth.txt paired line by line (they must then be as long as each other)."""
    assoc = os.path.join(data, "associations.txt")
    if os.path.exists(assoc):
        return [tuple(r[:4]) for r in read_list(assoc)]
    rgb, depth = read_list(os.path.join(data, "rgb.txt")), read_list(os.path.join(data, "depth.txt"))
    if len(rgb) != len(depth):
        sys.exit("%s: no associations.txt and rgb.txt / depth.txt differ in length" % data)
    return [(r[0], r[1], d[0], d[1]) for r, d in zip(rgb, depth)]


def write_lists(out, pairs):
    with open(os.path.join(out, "rgb.txt"), "w") as f:
        f.writelines("%s %s\n" % (p[0], p[1]) for p in pairs)
    with open(os.path.join(out, "depth.txt"), "w") as f:
        f.writelines("%s %s\n" % (p[2], p[3]) for p in pairs)


def references(folder):
    """The reference trajectories' file names in `folder`: groundtruth_*.txt, then
    groundtruth.txt (7-Scenes: the SfM one first)."""
    names = sorted(f for f in os.listdir(folder) if f.startswith("groundtruth_") and
                   f.endswith(".txt"))
    return names + (["groundtruth.txt"] if os.path.exists(os.path.join(folder,
                                                                        "groundtruth.txt")) else [])


def copy_references(data, out):
    for name in references(data):
        shutil.copy(os.path.join(data, name), out)


def ground_truth(data, name):
    """(timestamps array, lines) of data/NAME."""
    rows = read_list(os.path.join(data, name))
    return np.array([float(r[0]) for r in rows]), rows


def image_variant(data, out, n, transform):
    """The first n frames of `data`, passed through transform(colour, depth), with the same
    timestamps and ground truth."""
    os.makedirs(os.path.join(out, "rgb"))
    os.makedirs(os.path.join(out, "depth"))
    pairs = []
    for i, (trgb, rgb, tdepth, depth) in enumerate(read_pairs(data)[:n]):
        colour = np.asarray(o3d.io.read_image(os.path.join(data, rgb)))
        d = np.asarray(o3d.io.read_image(os.path.join(data, depth)))
        colour, d = transform(colour, d)
        name = "%06d.png" % i
        o3d.io.write_image(os.path.join(out, "rgb", name),
                           o3d.geometry.Image(np.ascontiguousarray(colour)))
        o3d.io.write_image(os.path.join(out, "depth", name),
                           o3d.geometry.Image(np.ascontiguousarray(d)))
        pairs.append((trgb, "rgb/" + name, tdepth, "depth/" + name))
    write_lists(out, pairs)
    copy_references(data, out)


def list_variant(data, out, order, retime):
    """A TUM list over `data`'s own files (absolute paths) in the given frame order; with
    `retime`, frames get fresh 30 Hz timestamps and the ground-truth pose nearest to their
    original time (within 20 ms)."""
    os.makedirs(out)
    pairs = read_pairs(data)
    truths = {name: ground_truth(data, name) for name in references(data)}
    rows, gt_rows = [], {name: [] for name in truths}
    for k, i in enumerate(order):
        trgb, rgb, tdepth, depth = pairs[i]
        if retime:
            t = "%.6f" % (float(pairs[0][0]) + k / 30.0)
            for name, (stamps, gt) in truths.items():
                j = int(np.argmin(np.abs(stamps - float(trgb))))
                if abs(stamps[j] - float(trgb)) < 0.02:
                    gt_rows[name].append(" ".join([t] + gt[j][1:]) + "\n")
            trgb = tdepth = t
        rows.append((trgb, os.path.join(data, rgb), tdepth, os.path.join(data, depth)))
    write_lists(out, rows)
    if retime:
        for name, lines in gt_rows.items():
            with open(os.path.join(out, name), "w") as f:
                f.writelines(lines)
    else:
        copy_references(data, out)


def camera_args(config):
    """[camera], [depth_camera] and [tum] of a preset, as --set arguments one can change."""
    values, section = {}, None
    with open(config) as f:
        for line in f:
            line = line.split("#")[0].strip()
            if line.startswith("["):
                section = line.strip("[]")
            elif "=" in line and section in ("camera", "depth_camera", "tum"):
                k, v = (s.strip() for s in line.split("=", 1))
                values["%s.%s" % (section, k)] = v
    return values


def run(build, seq, config, out, overrides, extra=()):
    args = [os.path.join(build, "bin", "semantic-mapper"), seq, "--config", config, "--out", out,
            "--quiet", "--set", "segmentation.backend=none", "--set", "output.snapshots=false",
            "--set", "output.annotated_rawlog=false", "--set", "local_mapping.threaded=false"]
    for k, v in overrides.items():
        args += ["--set", "%s=%s" % (k, v)]
    subprocess.run(args + list(extra), check=True, stdout=subprocess.DEVNULL)
    if seq.endswith(".rawlog"):  # tum2rawlog wrote NAME_groundtruth*.txt beside it
        stem = seq[:-len(".rawlog")]
        gts = sorted(glob.glob(stem + "_groundtruth_*.txt")) + [stem + "_groundtruth.txt"]
    else:
        gts = [os.path.join(seq, name) for name in references(seq)]
    rmses = []
    for gt in gts:
        ate = subprocess.run([os.path.join(build, "bin", "smap-eval"), "ate", gt,
                              os.path.join(out, "trajectory.txt")],
                             check=True, capture_output=True, text=True).stdout
        rmses.append((os.path.basename(gt), float(re.search(r"rmse\s+([0-9.]+)", ate).group(1))))
    with open(os.path.join(out, "trajectory.txt")) as f:
        posed = sum(1 for l in f if l.strip() and not l.startswith("#"))
    return posed, rmses


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data",
                                                   "7scenes-redkitchen"))
    ap.add_argument("--config", default=os.path.join(ROOT, "config", "7scenes.ini"))
    ap.add_argument("--first", type=int, default=300)
    a = ap.parse_args()
    data = os.path.abspath(a.data)
    n_all = len(read_pairs(data))
    n = min(a.first, n_all)
    cam = camera_args(a.config)
    w, h = int(cam["camera.width"]), int(cam["camera.height"])
    half, crop = dict(cam), dict(cam)
    top = (h - h * 9 // 12) // 2 if w * 3 == h * 4 else 0
    for section in ("camera", "depth_camera"):
        if section + ".fx" not in cam:
            continue
        c = lambda key: float(cam["%s.%s" % (section, key)])
        half.update({section + ".width": int(c("width")) // 2,
                     section + ".height": int(c("height")) // 2,
                     section + ".fx": c("fx") / 2, section + ".fy": c("fy") / 2,
                     section + ".cx": (c("cx") - 0.5) / 2, section + ".cy": (c("cy") - 0.5) / 2})
        crop.update({section + ".height": int(c("height")) - 2 * top,
                     section + ".cy": c("cy") - top})

    def halve(c, d):
        c = c[: h // 2 * 2, : w // 2 * 2].astype(np.float32)
        c = c.reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3)).round().astype(np.uint8)
        return c, d[::2, ::2]

    def holes(c, d):
        d = d.copy()
        d[d == 0] = 65535
        return c, d

    with tempfile.TemporaryDirectory() as work:
        def p(name):
            return os.path.join(work, name)

        print("building the variants in %s ..." % work, flush=True)
        list_variant(data, p("forward-backward"), list(range(n_all)) + list(range(n_all))[::-1],
                     True)
        list_variant(data, p("first"), list(range(n)), False)
        image_variant(data, p("half"), n, halve)
        image_variant(data, p("holes"), n, holes)
        image_variant(data, p("crop"), n, lambda c, d: (c[top:h - top], d[top:h - top]))
        subprocess.run([os.path.join(a.build, "bin", "tum2rawlog"), p("holes"),
                        p("holes.rawlog"), "--config", a.config], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        rows = [
            ("forward-backward", p("forward-backward"), cam, ()),
            ("first-%d" % n, p("first"), cam, ()),
            ("half-size", p("half"), half, ()),
            ("holes-65535", p("holes"), cam, ()),
            ("via-rawlog", p("holes.rawlog"), {}, ()),
            ("crop-16x9", p("crop"), crop, ()),
        ] + [("stride-%d" % s, data, cam, ("--set", "input.stride=%d" % s)) for s in (2, 3, 4)]
        trajectories = {}
        for name, seq, overrides, extra in rows:
            out = p("out-" + name)
            posed, rmses = run(a.build, seq, a.config, out, overrides, extra)
            frames = {"forward-backward": 2 * n_all, "stride-2": (n_all + 1) // 2,
                      "stride-3": (n_all + 2) // 3, "stride-4": (n_all + 3) // 4}.get(name, n)
            with open(os.path.join(out, "trajectory.txt")) as f:
                trajectories[name] = f.read()
            same = ""
            if name in ("holes-65535", "via-rawlog"):
                same = ", trajectory identical to first-%d: %s" % (
                    n, "yes" if trajectories[name] == trajectories["first-%d" % n] else "NO")
            print("%-17s %4d / %4d frames with a pose, ATE RMSE %s%s"
                  % (name, posed, frames,
                     ", ".join("%.1f mm vs %s" % (1000 * r, g) for g, r in rmses), same),
                  flush=True)


if __name__ == "__main__":
    main()
