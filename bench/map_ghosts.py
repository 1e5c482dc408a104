#!/usr/bin/python3
"""People left in a semantic point map, measured against the map of the same frames without
people: semantic-mapper's semantic_points.ply of a composite (people walked into a real
recording by smap-synth --composite-onto) against the one of the original recording.

For each MAP: its points, the "ghosts" (points farther than --distance from every point of the
people-free map: what the people left behind, plus whatever the two runs map differently; two
runs on the same people-free frames give about 0.2 %), their labels, and the people-free map's
coverage (its points with a MAP point within --distance: what removing the people cost).
Both maps must share the world frame, which semantic-mapper's do when both runs start at the
same frame (world = first tracked camera).

Needs Open3D (Debian python3-open3d) and numpy.
Usage: bench/map_ghosts.py PEOPLE_FREE.ply MAP.ply [MAP.ply ...] [--distance 0.05]
"""
import argparse
import sys

import numpy as np

try:
    import open3d as o3d
except ImportError:
    sys.exit("map_ghosts.py needs Open3D: apt-get install python3-open3d")

VERTEX = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("red", "u1"), ("green", "u1"),
                   ("blue", "u1"), ("label", "u1"), ("confidence", "<f4")])


def read_map(path):
    """The vertices of a CSemanticPointsMap PLY (binary, the layout semantic-mapper writes)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply") or end < 0:
        sys.exit("%s: not a PLY file" % path)
    header = data[:end].decode("ascii", "replace").split("\n")
    names = [l.split()[2] for l in header if l.startswith("property")]
    if names != list(VERTEX.names) or "format binary_little_endian 1.0" not in header:
        sys.exit("%s: expected semantic-mapper's binary point layout %s, found %s"
                 % (path, list(VERTEX.names), names))
    count = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    start = end + len(b"end_header\n")
    return np.frombuffer(data[start:start + count * VERTEX.itemsize], dtype=VERTEX)


def cloud(v):
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(
        np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("reference")
    ap.add_argument("maps", nargs="+")
    ap.add_argument("--distance", type=float, default=0.05, help="metres (default 0.05)")
    a = ap.parse_args()
    ref = cloud(read_map(a.reference))
    for path in a.maps:
        v = read_map(path)
        pts = cloud(v)
        to_ref = np.asarray(pts.compute_point_cloud_distance(ref))
        to_map = np.asarray(ref.compute_point_cloud_distance(pts))
        ghost = to_ref > a.distance
        labels, counts = np.unique(v["label"][ghost], return_counts=True)
        print("%s: %d points, ghosts %d (%.2f %%; labels %s), people-free map covered %.2f %%"
              % (path, len(v), ghost.sum(), 100.0 * ghost.mean(),
                 ", ".join("%d: %d" % lc for lc in zip(labels.tolist(), counts.tolist())),
                 100.0 * (to_map <= a.distance).mean()))


if __name__ == "__main__":
    main()
