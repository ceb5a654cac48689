#!/usr/bin/python3
# Training data for sarmap's DGCNN: simulates procedurally generated arenas
# with `sarmap simulate --random SEED` (sensor noise and dropout included),
# cuts every n-th frame into square cells of --block-size (1 m by default;
# the shipped model's are 1.5 m) on a grid fixed in the world frame, as the
# C++ engine's blocks (engine/semantic/dgcnn/block_partition.hpp), drops
# cells with fewer than min_points points and stores each kept block's world
# points and ground-truth labels (docs/training.md).
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


def collect(sarmap_exe, seeds, every, block_size, min_points, keep_points, rng):
    points, labels, offsets, origins, arena = [], [], [0], [], []
    for seed in seeds:
        with tempfile.TemporaryDirectory(prefix=f"sarmap-sim-{seed}-") as folder:
            subprocess.run([sarmap_exe, "simulate", "--random", str(seed), "--seed", str(seed), "--out", folder,
                            "--quiet"], check=True)
            blocks = 0
            for xyz, lab in sequence_frames(folder, every):
                for origin, idx in cells(xyz, block_size, min_points):
                    if len(idx) > keep_points:  # a uniform subset; training draws its sample from it
                        idx = np.sort(rng.choice(idx, keep_points, replace=False))
                    points.append(xyz[idx].astype(np.float32))
                    labels.append(lab[idx])
                    offsets.append(offsets[-1] + len(idx))
                    origins.append(origin)
                    arena.append(seed)
                    blocks += 1
        print(f"arena {seed}: {blocks} blocks", flush=True)
    return {
        "points": np.concatenate(points), "labels": np.concatenate(labels),
        "offsets": np.array(offsets, dtype=np.int64), "origins": np.array(origins, dtype=np.float64),
        "arena": np.array(arena, dtype=np.int64),
        "block_size": np.float64(block_size), "min_points": np.int64(min_points),
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
    parser.add_argument("--out", required=True, help=".npz file to write")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(12345)
    data = collect(args.sarmap, parse_seeds(args.seeds), args.every, args.block_size, args.min_points,
                   args.keep_points, rng)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    np.savez(args.out, **data)
    counts = np.bincount(data["labels"], minlength=6)
    print(f"{len(data['arena'])} blocks, {len(data['labels'])} points, per class {counts.tolist()} -> {args.out}")


if __name__ == "__main__":
    main(sys.argv[1:])
