#!/usr/bin/python3
"""Baseline for the tracking accuracy target: Open3D's RGB-D odometry (hybrid photometric +
geometric term), frame to frame, over a TUM-layout folder. Writes a TUM trajectory.

Needs Debian's python3-open3d (not part of the project's install step: a benchmark tool only).
Usage: bench/open3d_rgbd_odometry.py FOLDER OUT.txt [--fx 585 --fy 585 --cx 320 --cy 240
       --depth-factor 1000 --max-frames N]
"""
import argparse
import os
import sys
import time

import numpy as np


def read_associations(folder):
    path = os.path.join(folder, "associations.txt")
    pairs = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            t_rgb, rgb, _t_depth, depth = line.split()[:4]
            pairs.append((float(t_rgb), os.path.join(folder, rgb), os.path.join(folder, depth)))
    return pairs


def quaternion_from_matrix(R):
    w = np.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2.0
    x = np.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2.0
    y = np.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2.0
    z = np.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2.0
    x = np.copysign(x, R[2, 1] - R[1, 2])
    y = np.copysign(y, R[0, 2] - R[2, 0])
    z = np.copysign(z, R[1, 0] - R[0, 1])
    return x, y, z, w


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("out")
    ap.add_argument("--fx", type=float, default=585.0)
    ap.add_argument("--fy", type=float, default=585.0)
    ap.add_argument("--cx", type=float, default=320.0)
    ap.add_argument("--cy", type=float, default=240.0)
    ap.add_argument("--depth-factor", type=float, default=1000.0)
    ap.add_argument("--max-frames", type=int, default=0)
    a = ap.parse_args()
    import open3d as o3d

    pairs = read_associations(a.folder)
    if a.max_frames:
        pairs = pairs[: a.max_frames]
    first = o3d.io.read_image(pairs[0][1])
    h, w = np.asarray(first).shape[:2]
    K = o3d.camera.PinholeCameraIntrinsic(w, h, a.fx, a.fy, a.cx, a.cy)
    option = o3d.pipelines.odometry.OdometryOption()
    jacobian = o3d.pipelines.odometry.RGBDOdometryJacobianFromHybridTerm()

    def load(i):
        colour = o3d.io.read_image(pairs[i][1])
        depth = o3d.io.read_image(pairs[i][2])
        return o3d.geometry.RGBDImage.create_from_color_and_depth(
            colour, depth, depth_scale=a.depth_factor, depth_trunc=4.0,
            convert_rgb_to_intensity=True)

    T_world_cam = np.eye(4)
    poses = [(pairs[0][0], T_world_cam.copy())]
    prev = load(0)
    failures = 0
    t0 = time.time()
    for i in range(1, len(pairs)):
        cur = load(i)
        ok, T_prev_cur_inv, _info = o3d.pipelines.odometry.compute_rgbd_odometry(
            cur, prev, K, np.eye(4), jacobian, option)
        # compute_rgbd_odometry(source, target) returns T mapping source points into target:
        # here source = current, target = previous, i.e. T_prev_cur.
        if ok:
            T_world_cam = T_world_cam @ T_prev_cur_inv
        else:
            failures += 1
        poses.append((pairs[i][0], T_world_cam.copy()))
        prev = cur
    elapsed = time.time() - t0
    with open(a.out, "w") as f:
        f.write("# Open3D RGB-D odometry (hybrid term), frame to frame\n")
        for t, T in poses:
            x, y, z, qw = quaternion_from_matrix(T[:3, :3])[0:3] + (quaternion_from_matrix(T[:3, :3])[3],)
            f.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" %
                    (t, T[0, 3], T[1, 3], T[2, 3], x, y, z, qw))
    print("open3d odometry: %d frames, %d failures, %.1f frames/s" %
          (len(pairs), failures, len(pairs) / elapsed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
