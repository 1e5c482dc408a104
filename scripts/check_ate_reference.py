#!/usr/bin/env python3
"""Cross-checks `smap-eval ate` against an independent NumPy implementation of the TUM RGB-D
benchmark's ATE (greedy timestamp association, Horn/SVD SE(3) alignment, per-pose translation
error statistics) on a real ground-truth trajectory and a perturbed copy of it.

Exit codes: 0 agree to --tolerance, 1 disagree or error, 77 skipped (ground truth absent and
CI is not "true").
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np


def read_trajectory(path):
    stamps, xyz, quat = [], [], []
    with open(path) as f:
        for line in f:
            line = line.replace(",", " ").replace("\t", " ").strip()
            if not line or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()]
            stamps.append(v[0])
            xyz.append(v[1:4])
            quat.append(v[4:8])
    return np.array(stamps), np.array(xyz), np.array(quat)


def associate(a, b, offset, max_difference):
    candidates = []
    for i, ta in enumerate(a):
        for j in np.nonzero(np.abs(b + offset - ta) < max_difference)[0]:
            candidates.append((abs(ta - (b[j] + offset)), i, int(j)))
    candidates.sort()
    used_a, used_b, matches = set(), set(), []
    for _, i, j in candidates:
        if i in used_a or j in used_b:
            continue
        used_a.add(i)
        used_b.add(j)
        matches.append((i, j))
    matches.sort()
    return matches


def align_horn(model, data):
    """Rotation R and translation t minimising |data - (R model + t)|; points are rows."""
    mu_m, mu_d = model.mean(axis=0), data.mean(axis=0)
    W = (data - mu_d).T @ (model - mu_m)
    U, _, Vt = np.linalg.svd(W)
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        S[2, 2] = -1
    R = U @ S @ Vt
    return R, mu_d - R @ mu_m


def quat_to_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--smap-eval", required=True)
    ap.add_argument("--groundtruth", required=True)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--seed", type=int, default=20261121)
    args = ap.parse_args()

    if not os.path.exists(args.groundtruth):
        if os.environ.get("CI") == "true":
            print(f"FAIL: required ground truth missing: {args.groundtruth}")
            return 1
        print(f"SKIP: ground truth not found: {args.groundtruth} (needs ../shared)")
        return 77
    os.makedirs(args.workdir, exist_ok=True)

    t_gt, xyz_gt, q_gt = read_trajectory(args.groundtruth)
    rng = np.random.default_rng(args.seed)
    # Perturbed copy: another world frame, noise, a slow drift, 10% of poses dropped and
    # timestamps jittered by up to 8 ms (inside the 20 ms association window).
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = 0.8
    qr = np.concatenate([axis * np.sin(angle / 2), [np.cos(angle / 2)]])
    R = quat_to_matrix(qr)
    t = np.array([1.5, -0.7, 2.2])
    n = len(t_gt)
    drift = np.outer(np.linspace(0, 1, n), [0.05, -0.03, 0.02])
    xyz_est = (xyz_gt + drift + rng.normal(scale=0.02, size=(n, 3))) @ R.T + t
    keep = rng.random(n) > 0.1
    t_est = t_gt + rng.uniform(-0.008, 0.008, size=n)
    est_path = os.path.join(args.workdir, "perturbed.txt")
    with open(est_path, "w") as f:
        f.write("# perturbed copy of %s (seed %d)\n" % (args.groundtruth, args.seed))
        for i in np.nonzero(keep)[0]:
            f.write("%.9f %.9f %.9f %.9f %s\n" % (t_est[i], *xyz_est[i], " ".join("%.9f" % v for v in q_gt[i])))

    # Reference computation, from the files as written.
    t_e, x_e, _ = read_trajectory(est_path)
    matches = associate(t_gt, t_e, 0.0, 0.02)
    gt_pts = np.array([xyz_gt[i] for i, _ in matches])
    est_pts = np.array([x_e[j] for _, j in matches])
    Rr, tr = align_horn(est_pts, gt_pts)
    err = np.linalg.norm(gt_pts - (est_pts @ Rr.T + tr), axis=1)
    ref = {"rmse": float(np.sqrt(np.mean(err ** 2))), "mean": float(np.mean(err)), "median": float(np.median(err)),
           "std": float(np.std(err)), "min": float(np.min(err)), "max": float(np.max(err)),
           "pairs": len(matches), "coverage": len(matches) / len(t_gt)}

    json_path = os.path.join(args.workdir, "ate.json")
    subprocess.run([args.smap_eval, "ate", args.groundtruth, est_path, "--json", json_path], check=True)
    with open(json_path) as f:
        got = json.load(f)

    # The longest run of ground-truth rows (time order) that no pair uses.
    paired = np.zeros(len(t_gt), bool)
    paired[[i for i, _ in matches]] = True
    run = longest = 0
    for p in paired[np.argsort(t_gt, kind="stable")]:
        run = 0 if p else run + 1
        longest = max(longest, run)
    ref["longest_gap"] = longest
    got["longest_gap"] = got["longest_gap"]["poses"]

    worst = 0.0
    print("%-8s %20s %20s %12s" % ("key", "smap-eval", "reference", "|diff|"))
    for k, v in ref.items():
        d = abs(got[k] - v)
        worst = max(worst, d)
        print("%-8s %20.12f %20.12f %12.3e" % (k, got[k], v, d))
    if worst > args.tolerance:
        print("FAIL: largest difference %.3e > %.1e" % (worst, args.tolerance))
        return 1
    print("OK: smap-eval agrees with the independent reference to %.3e (tolerance %.0e)" % (worst, args.tolerance))
    return 0


if __name__ == "__main__":
    sys.exit(main())
