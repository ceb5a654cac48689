#!/usr/bin/python3
# Joins training-block files of training_blocks.py (e.g. depth-camera and
# LiDAR blocks of the same arenas) into one, for train_dgcnn.py's --data:
#
#   /usr/bin/python3 tools/python/join_blocks.py depth.npz lidar.npz --out both.npz
#
# The files must share the block size; each block keeps its arena seed, and
# the joined file records each block's sensor (the `sensor` of its file) and
# mounting (`block_mount`, or the file's --sensor-args) and,
# when all files agree, how the blocks were cut (map cell, cuts).
import argparse
import os
import sys

import numpy as np


def per_block(data, key, file_key, default):
    """A per-block record of a training-block file: `key` when it has one, else its one `file_key` (or
    `default`) repeated for each block, as files written before the per-block record hold it."""
    if key in data:
        return data[key].astype(str)
    return np.full(len(data["arena"]), str(data[file_key]) if file_key in data else default).astype(str)


def join(paths):
    parts = [np.load(p) for p in paths]
    sizes = {float(d["block_size"]) for d in parts}
    if len(sizes) != 1:
        raise SystemExit(f"join_blocks.py: the files' block sizes differ: {sorted(sizes)}")
    points, labels, offsets, origins, arena, sensor, mount = [], [], [np.zeros(1, np.int64)], [], [], [], []
    base = 0
    for path, d in zip(paths, parts):
        for key in ("points", "labels", "offsets", "origins", "arena"):
            if key not in d:
                raise SystemExit(f"join_blocks.py: {path} has no '{key}': not a training_blocks.py file")
        points.append(d["points"])
        labels.append(d["labels"])
        offsets.append(d["offsets"][1:] + base)
        base += int(d["offsets"][-1])
        origins.append(d["origins"])
        arena.append(d["arena"])
        sensor.append(per_block(d, "block_sensor", "sensor", "depth"))
        mount.append(per_block(d, "block_mount", "sensor_args", ""))  # simulate options of its mounting
    # How the blocks were cut, when every file agrees (frames, or maps of one cell size and number of cuts).
    cut = {}
    for key in ("map_cell", "snapshots"):
        values = {d[key].item() if key in d else 0 for d in parts}
        if len(values) == 1:
            cut[key] = np.asarray(values.pop())
    return {
        **cut,
        "points": np.concatenate(points), "labels": np.concatenate(labels), "offsets": np.concatenate(offsets),
        "origins": np.concatenate(origins), "arena": np.concatenate(arena),
        "block_size": np.float64(sizes.pop()), "min_points": np.int64(min(int(d["min_points"]) for d in parts)),
        "block_sensor": np.concatenate(sensor), "block_mount": np.concatenate(mount),
        "joined_from": np.array([os.path.abspath(p) for p in paths]),
    }


def main(argv):
    parser = argparse.ArgumentParser(description="join training-block files into one")
    parser.add_argument("files", nargs="+", help="training_blocks.py .npz files")
    parser.add_argument("--out", required=True, help=".npz file to write")
    args = parser.parse_args(argv)
    data = join(args.files)
    np.savez(args.out, **data)
    kinds = {s: int((data["block_sensor"] == s).sum()) for s in sorted(set(data["block_sensor"]))}
    print(f"{len(data['arena'])} blocks ({kinds}), {len(data['labels'])} points -> {args.out}")


if __name__ == "__main__":
    main(sys.argv[1:])
