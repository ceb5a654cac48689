#!/usr/bin/python3
# Training data for sarmap's DGCNN: simulates procedurally generated arenas
# with `sarmap simulate --random SEED` (sensor noise and dropout included),
# cuts every n-th frame into square cells of --block-size (1 m by default;
# the shipped model's are 1.5 m) on a grid fixed in the world frame, as the
# C++ engine's blocks (engine/semantic/dgcnn/block_partition.hpp), drops
# cells with fewer than min_points points and stores each kept block's world
# points and ground-truth labels (docs/training.md).
#
# Map-level blocks (--map-cell C): the frames are accumulated instead, one
# point per C-metre cube (the first seen, as the engine's labelled point map,
# engine/semantic/map/labelled_point_map.hpp), and the accumulated map is cut
# after each of --snapshots evenly spaced frames, keeping the cells that grew
# since the last cut: the blocks the map classifier of `sarmap run` sees, at
# the stages it sees them. --sensor lidar (with --sensor-args for `sarmap
# simulate`) gives LiDAR arenas.
#
# --vary-mount draws each arena's sensor mounting from its seed (mount_args
# below: the camera's height, pitch and resolution; the LiDAR's rings,
# range and height), so one file holds the sensor variety the shipped model
# must cope with; each block records the mounting it was seen with.
#
# Features are NOT computed here: train_dgcnn.py draws the block's points
# afresh every epoch and computes features with dgcnn_reference.block_features,
# the one Python definition the C++ engine is tested against.
#
# The frames are read through the sarmap Python module (docs/python.md), so
# its build folder must be on PYTHONPATH:
#
#   PYTHONPATH=build/release/python /usr/bin/python3 tools/python/training_blocks.py \
#       --sarmap build/release/tools/sarmap/sarmap --seeds 1000-1059 --every 6 \
#       --out /tmp/sarmap-train/blocks.npz
import argparse
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np

try:
    import sarmap
except ImportError as error:
    sys.exit(f"training_blocks.py reads frames through the sarmap module: {error}; "
             "put its build folder on PYTHONPATH (e.g. PYTHONPATH=build/release/python)")

def sequence_frames(folder, every):
    """Yields (world xyz float64 (M, 3), labels uint8 (M,)) of every `every`-th frame."""
    for i, (cloud, _pose, _origin) in enumerate(sarmap.open_sequence(folder)):
        if i % every:
            continue
        xyz = cloud.xyz.astype(np.float64)
        keep = np.isfinite(xyz).all(1)
        yield xyz[keep], cloud.labels[keep]


def frames_list(folder, every):
    return list(sequence_frames(folder, every))


def map_points(frames, cell):
    """The accumulated map of a list of frames: (xyz (K, 3), labels (K,), birth (K,)) with one point per
    `cell`-metre cube, the first seen in frame order, and the index of the frame that added it."""
    xyz = np.concatenate([f[0] for f in frames]) if frames else np.zeros((0, 3))
    labels = np.concatenate([f[1] for f in frames]) if frames else np.zeros(0, np.uint8)
    frame = np.concatenate([np.full(len(f[0]), i, np.int64) for i, f in enumerate(frames)]) if frames else \
        np.zeros(0, np.int64)
    ijk = np.floor(xyz / cell).astype(np.int64) + (1 << 20)  # 21 bits a coordinate: +-26 km at 2.5 cm
    if len(ijk) and (ijk.min() < 0 or ijk.max() >= (1 << 21)):
        raise SystemExit(f"training_blocks.py: a point lies too far out for {cell} m map cells")
    keys = (ijk[:, 0] << 42) | (ijk[:, 1] << 21) | ijk[:, 2]
    _, first = np.unique(keys, return_index=True)  # the first occurrence of each cube
    first = np.sort(first)
    return xyz[first], labels[first], frame[first]


def map_snapshot_cells(frames, cell, snapshots, block_size, min_points):
    """Yields (origin, xyz, labels) of the map's cells that grew between evenly spaced cuts of the
    accumulated map (the last frame always cut), each with at least min_points points."""
    xyz, labels, birth = map_points(frames, cell)
    cuts = sorted(set(int(round(k * len(frames) / snapshots)) - 1 for k in range(1, snapshots + 1)))
    seen = {}
    for cut in cuts:
        now = birth <= cut
        sub_xyz, sub_labels = xyz[now], labels[now]
        for origin, idx in cells(sub_xyz, block_size, min_points):
            if seen.get(origin) == len(idx):
                continue  # unchanged since the last cut
            seen[origin] = len(idx)
            yield origin, sub_xyz[idx], sub_labels[idx]


def cells(xyz, block_size, min_points):
    """Yields (cell origin (x0, y0), point indices) of the kept cells of a cloud."""
    ij = np.floor(xyz[:, :2] / block_size).astype(np.int64)
    order = np.lexsort((ij[:, 0], ij[:, 1]))
    ij = ij[order]
    starts = np.flatnonzero(np.r_[True, (ij[1:] != ij[:-1]).any(1)])
    ends = np.r_[starts[1:], len(order)]
    for s, e in zip(starts, ends):
        if e - s >= min_points:
            yield (ij[s, 0] * block_size, ij[s, 1] * block_size), np.sort(order[s:e])


def arena_cells(folder, every, block_size, min_points, map_cell, snapshots):
    """Yields (origin, xyz, labels) of one simulated arena's blocks: per frame, or of its accumulated map."""
    if map_cell > 0:
        yield from map_snapshot_cells(frames_list(folder, every), map_cell, snapshots, block_size, min_points)
        return
    for xyz, lab in sequence_frames(folder, every):
        for origin, idx in cells(xyz, block_size, min_points):
            yield origin, xyz[idx], lab[idx]


# The mountings --vary-mount draws from: robots' depth cameras sit 0.3-1.0 m
# up, pitched 5-30 degrees down, at 320 x 240 or 640 x 480; their LiDARs
# have 16, 32 or 64 rings (with those rings' usual vertical fields of view),
# 12-30 m of range and sit 0.3-1.2 m up. Validation found the height the
# one that matters (PERF.md, "sensors it was not trained with").
LIDAR_RINGS = ((16, "-15,15"), (32, "-16,15"), (64, "-25,15"))
LIDAR_RANGES = (12, 20, 30)
CAMERA_SIZES = ((320, 240), (640, 480))


def mount_args(sensor, seed):
    """sarmap simulate options for the sensor mounting of arena `seed`, drawn from the seed alone."""
    rng = np.random.default_rng([seed, 0x6d6f756e74])  # "mount": apart from any other use of the seed
    if sensor == "lidar":
        rings, fov = LIDAR_RINGS[rng.integers(len(LIDAR_RINGS))]
        return ["--rings", str(rings), "--vertical-fov", fov,
                "--max-range", str(LIDAR_RANGES[rng.integers(len(LIDAR_RANGES))]),
                "--sensor-height", f"{rng.uniform(0.3, 1.2):.2f}"]
    width, height = CAMERA_SIZES[rng.integers(len(CAMERA_SIZES))]
    return ["--width", str(width), "--height", str(height), "--sensor-height", f"{rng.uniform(0.3, 1.0):.2f}",
            "--pitch", f"{rng.uniform(-30.0, -5.0):.1f}"]


def collect(sarmap_exe, seeds, every, block_size, min_points, keep_points, rng, sensor="depth", sensor_args=(),
            frames=0, map_cell=0.0, snapshots=4, vary_mount=False):
    points, labels, offsets, origins, arena, mounts = [], [], [0], [], [], []
    for seed in seeds:
        mount = mount_args(sensor, seed) if vary_mount else []
        mount_text = shlex.join(mount + list(sensor_args))  # what each of the arena's blocks records
        with tempfile.TemporaryDirectory(prefix=f"sarmap-sim-{seed}-") as folder:
            command = [sarmap_exe, "simulate", "--random", str(seed), "--seed", str(seed), "--out", folder, "--quiet",
                       "--sensor", sensor, *mount, *sensor_args]
            if frames > 0:
                command += ["--frames", str(frames)]
            subprocess.run(command, check=True)
            blocks = 0
            for origin, xyz, lab in arena_cells(folder, every, block_size, min_points, map_cell, snapshots):
                if len(xyz) > keep_points:  # a uniform subset; training draws its sample from it
                    keep = np.sort(rng.choice(len(xyz), keep_points, replace=False))
                    xyz, lab = xyz[keep], lab[keep]
                points.append(xyz.astype(np.float32))
                labels.append(lab)
                offsets.append(offsets[-1] + len(xyz))
                origins.append(origin)
                arena.append(seed)
                mounts.append(mount_text)
                blocks += 1
        print(f"arena {seed}: {blocks} blocks" + (f" ({shlex.join(mount)})" if mount else ""), flush=True)
    if not points:
        raise SystemExit("training_blocks.py: no block reached --min-points in any arena")
    return {
        "points": np.concatenate(points), "labels": np.concatenate(labels),
        "offsets": np.array(offsets, dtype=np.int64), "origins": np.array(origins, dtype=np.float64),
        "arena": np.array(arena, dtype=np.int64),
        "block_size": np.float64(block_size), "min_points": np.int64(min_points),
        "sensor": np.str_(sensor), "sensor_args": np.str_(shlex.join(sensor_args)),
        "map_cell": np.float64(map_cell), "snapshots": np.int64(snapshots if map_cell > 0 else 0),
        "block_mount": np.array(mounts, dtype=str),
    }


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        a, _, b = part.partition("-")
        seeds.extend(range(int(a), int(b or a) + 1))
    return seeds


def main(argv):
    parser = argparse.ArgumentParser(description="simulate random arenas and cut them into DGCNN training blocks")
    parser.add_argument("--sarmap", required=True, help="the sarmap executable")
    parser.add_argument("--seeds", required=True, help="arena seeds, e.g. 1000-1059 or 1,5,9")
    parser.add_argument("--every", type=int, default=6, help="use every n-th frame (neighbours overlap heavily)")
    parser.add_argument("--block-size", type=float, default=1.0)
    parser.add_argument("--min-points", type=int, default=500)
    parser.add_argument("--keep-points", type=int, default=2048, help="points stored per block at most")
    parser.add_argument("--sensor", choices=["depth", "lidar"], default="depth", help="sarmap simulate's sensor")
    parser.add_argument("--sensor-args", default="", help='more options for sarmap simulate, e.g. "--rings 32"')
    parser.add_argument("--frames", type=int, default=0, help="simulate only the first N frames (0: all)")
    parser.add_argument("--vary-mount", action="store_true",
                        help="draw each arena's sensor mounting from its seed (height, pitch and resolution of a "
                             "camera; rings, range and height of a LiDAR); --sensor-args still apply after it")
    parser.add_argument("--map-cell", type=float, default=0.0,
                        help="cut the accumulated map (one point per cube of this size, e.g. 0.025) instead of "
                             "each frame")
    parser.add_argument("--snapshots", type=int, default=4,
                        help="with --map-cell: cut the map this many times along the run, keeping grown cells")
    parser.add_argument("--out", required=True, help=".npz file to write")
    args = parser.parse_args(argv)
    if args.map_cell < 0 or (args.map_cell > 0 and args.map_cell < 0.01):
        parser.error("--map-cell must be 0 (per frame) or at least 0.01 m")
    if args.snapshots < 1 or args.every < 1:
        parser.error("--snapshots and --every must be at least 1")
    rng = np.random.default_rng(12345)
    data = collect(args.sarmap, parse_seeds(args.seeds), args.every, args.block_size, args.min_points,
                   args.keep_points, rng, args.sensor, shlex.split(args.sensor_args), args.frames, args.map_cell,
                   args.snapshots, args.vary_mount)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    np.savez(args.out, **data)
    counts = np.bincount(data["labels"], minlength=6)
    print(f"{len(data['arena'])} blocks, {len(data['labels'])} points, per class {counts.tolist()} -> {args.out}")


if __name__ == "__main__":
    main(sys.argv[1:])
