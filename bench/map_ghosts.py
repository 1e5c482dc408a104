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

With --people COMPOSITE (an smap-synth folder: a --composite-onto composite or a preset), the
ghosts are also split by where they are: "where a person was" are those within 0.5 m of the
vertical axis of a person (from the feet up to 2 m, along meta.json's world_up, or z for a
preset, whose world is z up) at some frame of objects/person*.txt,
the definition of people left in the map (points where a person was that the
people-free run does not produce); the rest are the two runs' other differences. The map is
put in the composite's world frame by the run's trajectory.txt beside it (its first pose
against the composite's groundtruth.txt). Stricter, "on a person's surface" are the ghosts
where the folder drew a person at some frame (its labels/ pixels of class person, PASCAL VOC 15,
at their exact depth, by the ground-truth pose: every person, standing, walking or seated): a point within 2 cm of such a sample, a voxel holding one. For an
octomap, those whose place the people-free run saw free (a free leaf of its .bt) are people
left in the map: the other run shows the place empty, and a person was drawn there.

Octomaps too: given semantic_octomap.bt files (OctoMap's binary format, occupancy only), the
occupied voxels are compared the same way by their centres, a voxel being a ghost when no
occupied voxel of the people-free octomap lies within max(--distance, 1.5 x resolution) (its
own place or a face or edge neighbour); labels are not in .bt files.

Needs Open3D (Debian python3-open3d) and numpy; --people also OpenCV (python3-opencv).
Usage: bench/map_ghosts.py PEOPLE_FREE.ply MAP.ply [MAP.ply ...] [--distance 0.05]
                           [--people COMPOSITE_DIR]
       bench/map_ghosts.py PEOPLE_FREE.bt MAP.bt [MAP.bt ...] [--distance 0.05]
                           [--people COMPOSITE_DIR]
"""
import argparse
import glob
import json
import os
import sys

import numpy as np

try:
    import open3d as o3d
except ImportError:
    sys.exit("map_ghosts.py needs Open3D: apt-get install python3-open3d")

POINT_REACH = 0.02  # metres: a point map's point lies on a person's surface (poses ~1 cm apart)
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


class Octomap:
    """An OctoMap .bt file (tree depth 16): the centres of its occupied voxels (an N x 3 array;
    pruned occupied leaves expanded into voxels of the resolution), its resolution, and its free
    leaves, to ask whether a place was seen free."""

    DEPTH, HALF_RANGE = 16, 1 << 15

    def __init__(self, path):
        occupied, self.free, self.res = read_octomap_leaves(path)
        centres = []
        for (kx, ky, kz), depth in occupied:
            n = 1 << (self.DEPTH - depth)
            r = np.arange(n)
            g = np.stack(np.meshgrid(kx + r, ky + r, kz + r, indexing="ij"),
                         axis=-1).reshape(-1, 3)
            centres.append((g - self.HALF_RANGE + 0.5) * self.res)
        self.occupied = np.concatenate(centres) if centres else np.zeros((0, 3))

    def seen_free(self, points):
        """Per point (the map's frame): inside a free leaf."""
        keys = np.floor(points / self.res).astype(np.int64) + self.HALF_RANGE
        out = np.zeros(len(points), dtype=bool)
        for i, key in enumerate(keys):
            out[i] = any((d, tuple(int(k) >> (self.DEPTH - d) for k in key)) in self.free
                         for d in range(1, self.DEPTH + 1))
        return out


def read_octomap_leaves(path):
    """The occupied leaves of an OctoMap .bt file as (key min corner, depth), its free leaves as
    a set of (depth, key >> (16 - depth)), and the resolution."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"# Octomap OcTree binary file"):
        sys.exit("%s: not an OctoMap binary (.bt) file" % path)
    res, pos = None, 0
    while True:
        end = data.index(b"\n", pos)
        line = data[pos:end].decode("ascii", "replace").strip()
        pos = end + 1
        if line.startswith("res "):
            res = float(line.split()[1])
        if line == "data":
            break
    if res is None:
        sys.exit("%s: no resolution in the header" % path)
    depth_max = Octomap.DEPTH
    occupied, free = [], set()  # (key min corner, depth); (depth, corner >> (16 - depth))
    stack = [((0, 0, 0), 0)]  # nodes whose two child bytes come next, depth-first
    while stack:
        corner, depth = stack.pop()
        bits = data[pos] | (data[pos + 1] << 8)
        pos += 2
        size = 1 << (depth_max - depth - 1)  # a child's edge in keys
        inner = []
        for i in range(8):
            code = (bits >> (2 * i)) & 3
            child = tuple(corner[a] + (size if (i >> a) & 1 else 0) for a in range(3))
            if code == 2:  # bits "01": occupied leaf
                occupied.append((child, depth + 1))
            elif code == 1:  # bits "10": free leaf
                free.add((depth + 1, tuple(c >> (depth_max - depth - 1) for c in child)))
            elif code == 3:  # inner node: its children follow, in child order
                inner.append((child, depth + 1))
        stack.extend(reversed(inner))
    return occupied, free, res


def read_tum(path):
    """timestamp -> (R, t) of a TUM trajectory file (T_world_cam)."""
    poses = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(x) for x in line.split()]
        x, y, z, w = v[4:8]
        rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        poses[round(v[0], 4)] = (rot, np.array(v[1:4]))
    return poses


def world_up(meta_path):
    """The world's up vector: a composite's meta.json names it; a preset's world is z up."""
    meta = json.load(open(meta_path))
    if "world_up" in meta:
        return meta["world_up"]
    if str(meta.get("world_frame", "")).lower().startswith("z up"):
        return [0.0, 0.0, 1.0]
    sys.exit("%s: neither world_up nor a 'Z up' world_frame" % meta_path)


class PeoplePaths:
    """Where the composite's people were: their feet positions (every frame) and world up."""

    RADIUS, HEIGHT = 0.5, 2.0

    def __init__(self, composite):
        self.truth = read_tum(os.path.join(composite, "groundtruth.txt"))
        self.up = np.array(world_up(os.path.join(composite, "meta.json")))
        feet = [t for f in sorted(glob.glob(os.path.join(composite, "objects", "person*.txt")))
                for _, t in read_tum(f).values()]
        if not feet:
            sys.exit("%s: no objects/person*.txt" % composite)
        self.feet = np.array(feet)
        self.composite, self.person_surfaces = composite, None

    def surfaces(self):
        """The composite's PersonSurfaces, read on first use."""
        if self.person_surfaces is None:
            self.person_surfaces = PersonSurfaces(self.composite, self.truth)
        return self.person_surfaces

    def to_world(self, points, map_path):
        """The map's points in the composite's world frame, by the run's first pose."""
        run = read_tum(os.path.join(os.path.dirname(map_path) or ".", "trajectory.txt"))
        stamp = next((t for t in sorted(run) if t in self.truth), None)
        if stamp is None:
            sys.exit("%s: its trajectory.txt shares no timestamp with the ground truth"
                     % map_path)
        (r_est, t_est), (r_gt, t_gt) = run[stamp], self.truth[stamp]
        rot = r_gt @ r_est.T  # T_world_map = T_world_cam(truth) * T_map_cam(run)^-1
        return points @ rot.T + (t_gt - rot @ t_est)

    def near(self, world):
        """Per point: within RADIUS of a person's axis (feet to HEIGHT) at some frame."""
        out = np.zeros(len(world), dtype=bool)
        for start in range(0, len(world), 2000):
            p = world[start:start + 2000, None, :] - self.feet[None, :, :]
            h = p @ self.up
            radial = np.linalg.norm(p - h[..., None] * self.up, axis=2)
            out[start:start + 2000] = ((h >= 0) & (h <= self.HEIGHT) &
                                       (radial <= self.RADIUS)).any(axis=1)
        return out


def read_ini(path):
    """section -> key -> value of a camera.ini."""
    out, section = {}, None
    for line in open(path):
        line = line.split("#")[0].strip()
        if line.startswith("[") and line.endswith("]"):
            section = out.setdefault(line[1:-1].strip(), {})
        elif "=" in line and section is not None:
            key, value = line.split("=", 1)
            section[key.strip()] = value.strip()
    return out


class PersonSurfaces:
    """Where the folder drew a person: the pixels of class person in its labels/ images with
    their depth (exact for people), back-projected by each frame's ground-truth pose into the world frame
    and kept once per cell of STEP metres. A map element within reach of these samples lies on
    a person's surface, not merely near a person's path."""

    STEP, STRIDE = 0.01, 2  # metres; every STRIDE-th pixel in each direction
    PERSON = 15  # PASCAL VOC's person, smap-synth's label for every person it draws

    def __init__(self, composite, truth):
        import cv2  # Debian python3-opencv; only --people needs it
        ini = read_ini(os.path.join(composite, "camera.ini"))
        cam = {k: float(ini["camera"][k]) for k in ("fx", "fy", "cx", "cy")}
        factor = float(ini.get("tum", {}).get("depth_factor", 5000.0))
        cells = []
        for line in open(os.path.join(composite, "associations.txt")):
            if line.startswith("#") or not line.strip():
                continue
            stamp, _, _, depth_name = line.split()
            pose = truth.get(round(float(stamp), 4))
            name = os.path.basename(depth_name)
            labels = cv2.imread(os.path.join(composite, "labels", name), cv2.IMREAD_UNCHANGED)
            mask = None if labels is None else (labels == self.PERSON)
            depth = cv2.imread(os.path.join(composite, depth_name), cv2.IMREAD_UNCHANGED)
            if pose is None or mask is None or depth is None:
                sys.exit("%s: frame %s has no ground truth, label image or depth"
                         % (composite, stamp))
            cells.append(self.frame_cells(mask, depth / factor, cam, pose))
        cells = np.unique(np.concatenate(cells), axis=0) if cells else np.zeros((0, 3))
        self.points = (cells + 0.5) * self.STEP
        self.cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(self.points))

    def frame_cells(self, mask, depth, cam, pose):
        v, u = np.nonzero(mask[::self.STRIDE, ::self.STRIDE] &
                          (depth[::self.STRIDE, ::self.STRIDE] > 0))
        v, u = v * self.STRIDE, u * self.STRIDE
        z = depth[v, u]
        cam_pts = np.stack([(u - cam["cx"]) * z / cam["fx"], (v - cam["cy"]) * z / cam["fy"], z],
                           axis=1)
        rot, t = pose
        return np.unique(np.floor((cam_pts @ rot.T + t) / self.STEP).astype(np.int64), axis=0)

    def within(self, world, reach):
        """Per element: within REACH metres of a sample of a person's surface."""
        if len(world) == 0 or len(self.points) == 0:
            return np.zeros(len(world), dtype=bool)
        pts = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(world))
        return np.asarray(pts.compute_point_cloud_distance(self.cloud)) <= reach


def people_text(people, points, ghost, map_path, reach, seen_free=None):
    """The ghosts split by where they are: near a person's path (PeoplePaths.near), and on a
    person's surface (within REACH of where the composite drew one). SEEN_FREE, per ghost, says
    the people-free run saw its place free (octomaps): a ghost on a person's surface there is a
    person left in the map, not structure the other run lacks."""
    if people is None:
        return ""
    world = people.to_world(points[ghost], map_path)
    near = people.near(world)
    text = "; where a person was %d (%.2f %%), elsewhere %d" % (
        near.sum(), 100.0 * near.sum() / max(1, len(points)), (~near).sum())
    on = people.surfaces().within(world, reach)
    text += "; on a person's surface %d (%.3f %%)" % (on.sum(), 100.0 * on.sum() / max(1, len(points)))
    if seen_free is not None:
        text += ", of them seen free without people %d" % (on & seen_free).sum()
    return text


def octomap_ghosts(reference, paths, distance, people):
    ref_map = Octomap(reference)
    res = ref_map.res
    ref = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(ref_map.occupied))
    for path in paths:
        centres = Octomap(path).occupied
        vox = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(centres))
        to_ref = np.asarray(vox.compute_point_cloud_distance(ref))
        ghost = to_ref > max(distance, 1.5 * res)
        # a voxel holds a surface sample within half its diagonal of its centre
        text = people_text(people, centres, ghost, path, 0.87 * res,
                           ref_map.seen_free(centres[ghost]) if people else None)
        print("%s: %d occupied voxels, ghosts %d (%.2f %%)%s"
              % (path, len(centres), ghost.sum(), 100.0 * ghost.mean() if len(centres) else 0.0,
                 text))


def cloud(v):
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(
        np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("reference")
    ap.add_argument("maps", nargs="+")
    ap.add_argument("--distance", type=float, default=0.05, help="metres (default 0.05)")
    ap.add_argument("--people", help="the smap-synth folder (composite or preset): split "
                    "ghosts by where people were")
    a = ap.parse_args()
    people = PeoplePaths(a.people) if a.people else None
    if a.reference.endswith(".bt"):
        octomap_ghosts(a.reference, a.maps, a.distance, people)
        return
    ref = cloud(read_map(a.reference))
    for path in a.maps:
        v = read_map(path)
        pts = cloud(v)
        to_ref = np.asarray(pts.compute_point_cloud_distance(ref))
        to_map = np.asarray(ref.compute_point_cloud_distance(pts))
        ghost = to_ref > a.distance
        labels, counts = np.unique(v["label"][ghost], return_counts=True)
        print("%s: %d points, ghosts %d (%.2f %%; labels %s), people-free map covered %.2f %%%s"
              % (path, len(v), ghost.sum(), 100.0 * ghost.mean(),
                 ", ".join("%d: %d" % lc for lc in zip(labels.tolist(), counts.tolist())),
                 100.0 * (to_map <= a.distance).mean(),
                 people_text(people, np.asarray(pts.points), ghost, path, POINT_REACH)))


if __name__ == "__main__":
    main()
