"""TUM trajectory files (timestamp tx ty tz qx qy qz qw) for the bench scripts."""
import sys

import numpy as np


def read_tum(path):
    """{timestamp in ms: (translation, quaternion x y z w)}; exits naming the bad line."""
    poses = {}
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            if len(v) != 8:
                sys.exit("%s:%d: expected 8 numbers, got %d" % (path, number, len(v)))
            t, tx, ty, tz, qx, qy, qz, qw = (float(x) for x in v)
            poses[round(t * 1000)] = (np.array([tx, ty, tz]), np.array([qx, qy, qz, qw]))
    return poses


def rotation_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose_matrices(path):
    """{timestamp in ms: 4x4 T_world_cam}."""
    matrices = {}
    for stamp, (t, q) in read_tum(path).items():
        T = np.eye(4)
        T[:3, :3] = rotation_matrix(q)
        T[:3, 3] = t
        matrices[stamp] = T
    return matrices
