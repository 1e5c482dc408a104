#!/usr/bin/python3
"""How much an estimated trajectory rotates about each camera axis, against ground truth.

For consecutive windows of STEP frames, the relative rotation of the camera (in the first
frame's optical frame: x right, y down, z forward) is taken from both trajectories as a
rotation vector. Per axis, the least-squares scale s with est ~= s * gt over all windows says
whether the estimate turns less (s < 1) or more than the ground truth about that axis; the
same for the translation. A focal length error scales the pitch (x) and yaw (y) rotations but
leaves the roll (z) alone; a timing error scales all three.

Usage: bench/rotation_axes.py GROUNDTRUTH.txt ESTIMATE.txt [--step 30] [--window 100]
Both TUM format (timestamp tx ty tz qx qy qz qw); poses are paired by timestamp (1 ms).
"""
import argparse
import sys

import numpy as np
from tum_trajectory import read_tum, rotation_matrix as matrix


def rotation_vector(R):
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0))
    if angle < 1e-12:
        return np.zeros(3)
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return axis / (2 * np.sin(angle)) * angle


def relative_motions(poses, stamps, step):
    rot, trans = [], []
    for a, b in zip(stamps[:-step:step], stamps[step::step]):
        (ta, qa), (tb, qb) = poses[a], poses[b]
        Ra = matrix(qa)
        rot.append(rotation_vector(Ra.T @ matrix(qb)))
        trans.append(Ra.T @ (tb - ta))
    return np.array(rot), np.array(trans)


def scale(gt, est):
    denominator = gt @ gt
    return (gt @ est) / denominator if denominator > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("groundtruth")
    ap.add_argument("estimate")
    ap.add_argument("--step", type=int, default=30, help="frames per relative motion")
    ap.add_argument("--window", type=int, default=0,
                    help="also print the scales per window of this many frames")
    args = ap.parse_args()
    gt, est = read_tum(args.groundtruth), read_tum(args.estimate)
    stamps = sorted(set(gt) & set(est))
    if len(stamps) <= args.step:
        sys.exit("only %d poses in common: need more than --step %d" % (len(stamps), args.step))
    g_rot, g_t = relative_motions(gt, stamps, args.step)
    e_rot, e_t = relative_motions(est, stamps, args.step)
    print("%d poses in common, %d relative motions of %d frames" %
          (len(stamps), len(g_rot), args.step))
    print("rotation about x (pitch) %.3f, y (yaw) %.3f, z (roll) %.3f  [estimate / ground truth]" %
          tuple(scale(g_rot[:, k], e_rot[:, k]) for k in range(3)))
    print("total turn: ground truth %.1f deg, estimate %.1f deg" %
          (np.degrees(np.linalg.norm(g_rot, axis=1).sum()),
           np.degrees(np.linalg.norm(e_rot, axis=1).sum())))
    print("translation along x %.3f, y %.3f, z %.3f  [estimate / ground truth]" %
          tuple(scale(g_t[:, k], e_t[:, k]) for k in range(3)))
    if args.window > 0:
        per = max(1, args.window // args.step)
        for s in range(0, len(g_rot), per):
            g, e = g_rot[s:s + per], e_rot[s:s + per]
            print("  frames %5d-%5d: pitch %.2f yaw %.2f roll %.2f" %
                  ((s * args.step, (s + len(g)) * args.step) +
                   tuple(scale(g[:, k], e[:, k]) for k in range(3))))


if __name__ == "__main__":
    main()
