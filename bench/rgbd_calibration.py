#!/usr/bin/python3
"""Colour camera model of an RGB-D folder whose depth is not registered to colour.

Three checks for TUM-layout folders (rgb.txt / depth.txt or associations.txt), all numpy and
Open3D (Debian python3-open3d) for image reading only:

  edges DATA         Fits the colour camera (fx, fy, cx, cy) and the depth-to-colour offset
                     (tx, ty in metres) from single frames, without any pose: depth jumps,
                     mapped through the model into the colour image, should land on colour
                     edges. Prints the model that maximises the mean colour gradient there.
  photo DATA TRAJ    Photometric consistency of a trajectory (TUM format) under a model:
                     depth pixels of frame i+STEP, moved by the trajectory's relative pose and
                     projected into both colour images, should have the same grey level. Prints
                     the mean absolute difference (grey levels, clipped at 30; lower is better).
                     Comparing the ground truth and an estimate under one model says which of
                     the two the colour images support. With --fit, the colour model (focal
                     lengths, centre, offset and radial distortion k1, k2) is fitted to the
                     trajectory instead, starting from --colour: the lowest difference any such
                     camera gives that trajectory.
  register DATA OUT  Writes a copy of DATA (colour images linked, lists copied) whose depth
                     images are re-projected into the colour camera (nearest depth wins).

Models: --depth fx,fy,cx,cy (default 585,585,320,240, the 7-Scenes depth camera); --colour
fx,fy,cx,cy and --offset=tx,ty (metres; write "=" before a minus sign): a depth-frame point p
is p + offset in the colour camera frame (no rotation). Depth factor --depth-factor (7-Scenes 1000, TUM 5000).

Usage: bench/rgbd_calibration.py edges ../shared/data/7scenes-redkitchen
       bench/rgbd_calibration.py photo DATA DATA/groundtruth.txt --colour 526,529,320,238 \
           --offset=-0.024,0.002
       bench/rgbd_calibration.py photo DATA DATA/groundtruth.txt --fit --rounds 6
"""
import argparse
import os
import shutil
import sys

import numpy as np
from tum_trajectory import pose_matrices

try:
    import open3d as o3d
except ImportError:
    sys.exit("rgbd_calibration.py needs Open3D: apt-get install python3-open3d")

W, H = 640, 480


def parse_floats(text, count, name):
    values = text.split(",")
    if len(values) != count:
        sys.exit("--%s: expected %d comma-separated numbers, got '%s'" % (name, count, text))
    try:
        return np.array([float(v) for v in values])
    except ValueError:
        sys.exit("--%s: not a number in '%s'" % (name, text))


def frame_list(data):
    """(rgb path, depth path, timestamp) per frame, from associations.txt or the two lists."""
    assoc = os.path.join(data, "associations.txt")
    frames = []
    if os.path.exists(assoc):
        with open(assoc) as f:
            for line in f:
                v = line.split()
                if len(v) >= 4 and not line.startswith("#"):
                    frames.append((os.path.join(data, v[1]), os.path.join(data, v[3]), float(v[0])))
        return frames
    lists = []
    for name in ("rgb.txt", "depth.txt"):
        path = os.path.join(data, name)
        if not os.path.exists(path):
            sys.exit("%s: missing (and no associations.txt)" % path)
        with open(path) as f:
            lists.append([l.split() for l in f if l.strip() and not l.startswith("#")])
    depth_times = np.array([float(d[0]) for d in lists[1]])
    for r in lists[0]:
        k = int(np.argmin(np.abs(depth_times - float(r[0]))))
        if abs(depth_times[k] - float(r[0])) < 0.02:
            frames.append((os.path.join(data, r[1]), os.path.join(data, lists[1][k][1]), float(r[0])))
    return frames


def read_depth(path, factor):
    return np.asarray(o3d.io.read_image(path)).astype(np.float64) / factor


def box_blur(img, radius):
    kernel = np.ones(2 * radius + 1) / (2 * radius + 1)
    img = np.apply_along_axis(lambda r: np.convolve(r, kernel, "same"), 1, img)
    return np.apply_along_axis(lambda c: np.convolve(c, kernel, "same"), 0, img)


def read_grey(path, blur):
    grey = np.asarray(o3d.io.read_image(path)).astype(np.float64)
    if grey.ndim == 3:
        grey = grey[:, :, :3].mean(-1)
    return box_blur(grey, blur)


def back_project(u, v, z, depth_model):
    fx, fy, cx, cy = depth_model
    return np.stack([(u - cx) * z / fx, (v - cy) * z / fy, z], -1)


def project(points, colour, offset, radial=(0.0, 0.0)):
    """Pixel of depth-frame points in the colour camera; radial = (k1, k2) distortion."""
    fx, fy, cx, cy = colour
    x = (points[:, 0] + offset[0]) / points[:, 2]
    y = (points[:, 1] + offset[1]) / points[:, 2]
    r2 = x * x + y * y
    d = 1.0 + radial[0] * r2 + radial[1] * r2 * r2
    return x * d * fx + cx, y * d * fy + cy


def coordinate_search(cost, start, steps, rounds, label):
    """Minimises cost by walking each parameter while it improves, halving the steps per round."""
    best_p, best = np.array(start, float), cost(start)
    steps = np.array(steps, float)
    print("%s start %s: %.4f" % (label, np.round(best_p, 4), best), flush=True)
    for r in range(rounds):
        for k in range(len(best_p)):
            for sign in (1, -1):
                while True:
                    trial = best_p.copy()
                    trial[k] += sign * steps[k]
                    c = cost(trial)
                    if c >= best:
                        break
                    best_p, best = trial, c
        print("%s round %d: %s: %.4f" % (label, r + 1, np.round(best_p, 4), best), flush=True)
        steps /= 2
    return best_p, best


def cmd_edges(args, depth_model):
    frames = frame_list(args.data)[:: args.every]
    grid_u, grid_v = np.meshgrid(np.arange(W), np.arange(H))
    samples = []
    for rgb, depth, _ in frames:
        z = read_depth(depth, args.depth_factor)
        grey = read_grey(rgb, 1)
        gx = np.zeros_like(grey)
        gy = np.zeros_like(grey)
        gx[:, 1:-1] = grey[:, 2:] - grey[:, :-2]
        gy[1:-1] = grey[2:] - grey[:-2]
        gradient = box_blur(np.hypot(gx, gy), 1)
        # The near side of every depth jump larger than --jump.
        edge = np.zeros(z.shape, bool)
        both_x = (z[:, 1:] > 0) & (z[:, :-1] > 0)
        both_y = (z[1:] > 0) & (z[:-1] > 0)
        dx = z[:, 1:] - z[:, :-1]
        dy = z[1:] - z[:-1]
        edge[:, :-1] |= both_x & (dx > args.jump)
        edge[:, 1:] |= both_x & (dx < -args.jump)
        edge[:-1] |= both_y & (dy > args.jump)
        edge[1:] |= both_y & (dy < -args.jump)
        edge &= z > args.min_depth
        points = back_project(grid_u[edge], grid_v[edge], z[edge], depth_model)
        samples.append((points, gradient))
    print("%d frames, %d depth-edge pixels" % (len(samples), sum(len(s[0]) for s in samples)))

    def cost(p):
        values = []
        for points, gradient in samples:
            u, v = project(points, p[:4], p[4:])
            u = np.round(u).astype(int)
            v = np.round(v).astype(int)
            inside = (u >= 0) & (u < W) & (v >= 0) & (v < H)
            values.append(gradient[v[inside], u[inside]])
        return -np.mean(np.concatenate(values))

    # Equal focal lengths first (the cost is flat along some directions far from the optimum).
    start = np.concatenate([depth_model, [0.0, 0.0]])
    scan = []
    for f in np.arange(0.8, 1.1001, 0.025) * depth_model[0]:
        p = start.copy()
        p[0] = f
        p[1] = f * depth_model[1] / depth_model[0]
        scan.append((cost(p), f))
        print("focal %.1f: mean gradient %.3f" % (f, -scan[-1][0]))
    start[0] = min(scan)[1]
    start[1] = start[0] * depth_model[1] / depth_model[0]
    best, value = coordinate_search(cost, start, [10, 10, 5, 5, 0.01, 0.01], args.rounds, "edges")
    print("colour model: --colour %.1f,%.1f,%.1f,%.1f --offset=%.4f,%.4f (mean gradient %.3f)"
          % (*best[:4], best[4], best[5], -value))


def bilinear(img, u, v):
    u0 = np.floor(u).astype(int)
    v0 = np.floor(v).astype(int)
    inside = (u0 >= 2) & (u0 < W - 3) & (v0 >= 2) & (v0 < H - 3)
    a = u - u0
    b = v - v0
    u0 = np.clip(u0, 0, W - 2)
    v0 = np.clip(v0, 0, H - 2)
    value = ((1 - a) * (1 - b) * img[v0, u0] + a * (1 - b) * img[v0, u0 + 1]
             + (1 - a) * b * img[v0 + 1, u0] + a * b * img[v0 + 1, u0 + 1])
    return value, inside


def photo_pairs(args, poses, depth_model):
    """(T_ci_cj, depth points of frame j, grey i, grey j) for every pair with both poses."""
    frames = frame_list(args.data)
    grid_u, grid_v = np.meshgrid(np.arange(W), np.arange(H))
    pairs = []
    for i in range(0, len(frames) - args.step, args.every):
        j = i + args.step
        key_i, key_j = round(frames[i][2] * 1000), round(frames[j][2] * 1000)
        if key_i not in poses or key_j not in poses:
            continue
        z = read_depth(frames[j][1], args.depth_factor)
        valid = (z > args.min_depth) & (z < args.max_depth)
        points = back_project(grid_u[valid], grid_v[valid], z[valid], depth_model)[::3]
        pairs.append((np.linalg.inv(poses[key_i]) @ poses[key_j], points,
                      read_grey(frames[i][0], 2), read_grey(frames[j][0], 2)))
    return pairs


def photo_difference(pairs, model):
    """Mean clipped grey difference; model = fx, fy, cx, cy, tx, ty, k1, k2."""
    colour, offset, radial = model[:4], model[4:6], model[6:8]
    residuals = []
    for T_ci_cj, points, grey_i, grey_j in pairs:
        # The trajectory is the colour camera's; depth points go depth -> colour (offset) first.
        points_cj = points + np.array([offset[0], offset[1], 0.0])
        points_ci = points_cj @ T_ci_cj[:3, :3].T + T_ci_cj[:3, 3]
        zero = np.zeros(2)
        u_j, v_j = project(points_cj, colour, zero, radial)
        u_i, v_i = project(points_ci, colour, zero, radial)
        value_i, in_i = bilinear(grey_i, u_i, v_i)
        value_j, in_j = bilinear(grey_j, u_j, v_j)
        ok = in_i & in_j & (points_ci[:, 2] > 0)
        residuals.append(np.minimum(np.abs(value_i - value_j)[ok], 30))
    return np.mean(np.concatenate(residuals))


def cmd_photo(args, depth_model, colour, offset):
    pairs = photo_pairs(args, pose_matrices(args.trajectory), depth_model)
    if not pairs:
        sys.exit("%s: no frame pairs with both poses" % args.trajectory)
    model = np.concatenate([colour, offset, [0.0, 0.0]])
    print("%s: %d frame pairs %d apart, mean |grey difference| %.3f (clipped at 30)"
          % (args.trajectory, len(pairs), args.step, photo_difference(pairs, model)), flush=True)
    if args.fit:
        best, value = coordinate_search(lambda p: photo_difference(pairs, p), model,
                                        [10, 10, 5, 5, 0.01, 0.01, 0.05, 0.1], args.rounds,
                                        "photo fit")
        print("%s: best colour model --colour %.1f,%.1f,%.1f,%.1f --offset=%.4f,%.4f "
              "k1 %.3f k2 %.3f: mean |grey difference| %.3f"
              % (args.trajectory, *best, value))


def cmd_register(args, depth_model, colour, offset):
    if os.path.exists(args.out):
        sys.exit("%s: exists; give a new folder" % args.out)
    frames = frame_list(args.data)
    tmp = args.out.rstrip("/") + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for name in ("rgb.txt", "depth.txt", "associations.txt", "groundtruth.txt"):
        if os.path.exists(os.path.join(args.data, name)):
            shutil.copy(os.path.join(args.data, name), os.path.join(tmp, name))
    grid_u, grid_v = np.meshgrid(np.arange(W), np.arange(H))
    for n, (rgb, depth, _) in enumerate(frames):
        rel_rgb = os.path.relpath(rgb, args.data)
        rel_depth = os.path.relpath(depth, args.data)
        link = os.path.join(tmp, rel_rgb)
        os.makedirs(os.path.dirname(link), exist_ok=True)
        if not os.path.exists(link):
            os.symlink(os.path.abspath(rgb), link)
        raw = np.asarray(o3d.io.read_image(depth))
        valid = raw > 0
        points = back_project(grid_u[valid], grid_v[valid], raw[valid] / args.depth_factor,
                              depth_model)
        u, v = project(points, colour, offset)
        registered = np.full(H * W, np.iinfo(np.uint16).max, np.uint32)
        # Each depth pixel covers the four colour pixels around its projection; nearest wins.
        for du in (0, 1):
            for dv in (0, 1):
                uu = np.floor(u).astype(int) + du
                vv = np.floor(v).astype(int) + dv
                inside = (uu >= 0) & (uu < W) & (vv >= 0) & (vv < H)
                np.minimum.at(registered, vv[inside] * W + uu[inside], raw[valid][inside])
        registered[registered == np.iinfo(np.uint16).max] = 0
        out_path = os.path.join(tmp, rel_depth)
        os.makedirs(os.path.dirname(out_path), exist_ok=True)
        o3d.io.write_image(out_path, o3d.geometry.Image(registered.reshape(H, W).astype(np.uint16)))
        if (n + 1) % 100 == 0:
            print("%d / %d frames registered" % (n + 1, len(frames)), flush=True)
    os.rename(tmp, args.out)
    print("%s: %d frames; run with --set camera.fx=%g --set camera.fy=%g --set camera.cx=%g "
          "--set camera.cy=%g" % (args.out, len(frames), *colour))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("command", choices=["edges", "photo", "register"])
    parser.add_argument("data")
    parser.add_argument("target", nargs="?", help="photo: trajectory; register: output folder")
    parser.add_argument("--depth", default="585,585,320,240")
    parser.add_argument("--colour", default=None, help="fx,fy,cx,cy (default: --depth)")
    parser.add_argument("--offset", default="0,0", help="tx,ty in metres")
    parser.add_argument("--depth-factor", type=float, default=1000.0)
    parser.add_argument("--every", type=int, default=25, help="use every Nth frame")
    parser.add_argument("--step", type=int, default=10, help="photo: frames between the pair")
    parser.add_argument("--rounds", type=int, default=12, help="edges, photo --fit: search rounds")
    parser.add_argument("--fit", action="store_true",
                        help="photo: fit the colour model (with k1, k2) to the trajectory")
    parser.add_argument("--jump", type=float, default=0.1, help="edges: depth jump (m)")
    parser.add_argument("--min-depth", type=float, default=0.3)
    parser.add_argument("--max-depth", type=float, default=4.0)
    args = parser.parse_args()
    depth_model = parse_floats(args.depth, 4, "depth")
    colour = parse_floats(args.colour, 4, "colour") if args.colour else depth_model
    offset = parse_floats(args.offset, 2, "offset")
    if args.command == "edges":
        cmd_edges(args, depth_model)
    elif args.target is None:
        sys.exit("%s needs a %s" % (args.command,
                                    "trajectory" if args.command == "photo" else "output folder"))
    elif args.command == "photo":
        args.trajectory = args.target
        cmd_photo(args, depth_model, colour, offset)
    else:
        args.out = args.target
        cmd_register(args, depth_model, colour, offset)


if __name__ == "__main__":
    main()
