#!/usr/bin/env python3
"""Writes a DGCNN model of the paper's full size (k 20, emb 1024, 4096 points
per block) with random weights, for timing only: speed does not depend on the
weights' values. The block geometry, classes and normalisation are taken
from a given model (by default the shipped one), so `sarmap run --model OUT`
runs the same pipeline with the larger network (PERF.md, "Full-size DGCNN").

  python3 tools/python/full_size_model.py [--like MODEL] --out full.safetensors

Needs only numpy. The tensors follow the DGCNN authors' names, as
tools/python/export_safetensors.py writes them.
"""
import argparse
import json
import struct
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


def read_header(path):
    with open(path, "rb") as f:
        size = struct.unpack("<Q", f.read(8))[0]
        header = json.loads(f.read(size))
    return header.pop("__metadata__", {}), header


def full_size_shape(name, shape, emb, edge_features):
    """The tensor's shape in the full-size network (emb channels of global features)."""
    if name.startswith(("bn6.", "conv6.1.")):
        return [emb]
    if name == "conv6.0.weight":
        return [emb, shape[1], 1]
    if name == "conv7.0.weight":
        return [shape[0], emb + edge_features, 1]
    return shape


def random_tensor(name, shape, rng):
    if name.endswith(("running_mean", ".bias")):
        return (0.1 * rng.standard_normal(shape) if name.endswith(".bias") else np.zeros(shape)).astype(np.float32)
    if name.endswith("running_var"):
        return np.ones(shape, np.float32)
    if len(shape) == 1:  # a batch norm's scale
        return np.ones(shape, np.float32)
    fan_in = int(np.prod(shape[1:]))
    return (rng.standard_normal(shape) / np.sqrt(fan_in)).astype(np.float32)


def write_safetensors(path, tensors, metadata):
    header = {"__metadata__": metadata}
    offset = 0
    blobs = []
    for name in sorted(tensors):
        data = np.ascontiguousarray(tensors[name], dtype="<f4").tobytes()
        header[name] = {"dtype": "F32", "shape": list(tensors[name].shape), "data_offsets": [offset, offset + len(data)]}
        offset += len(data)
        blobs.append(data)
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)))
        f.write(text)
        for blob in blobs:
            f.write(blob)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--like", default=str(REPO / "datasets/models/ramps-dgcnn.safetensors"),
                    help="model whose block geometry, classes and normalisation to keep")
    ap.add_argument("--out", required=True)
    ap.add_argument("--k", type=int, default=20)
    ap.add_argument("--emb", type=int, default=1024)
    ap.add_argument("--points", type=int, default=4096)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    metadata, header = read_header(args.like)
    edge_features = 192  # the three EdgeConv outputs, 64 each
    rng = np.random.default_rng(args.seed)
    tensors = {name: random_tensor(name, full_size_shape(name, info["shape"], args.emb, edge_features), rng)
               for name, info in header.items()}
    metadata = {k: v for k, v in metadata.items() if k != "sarmap.training"}
    metadata.update({"sarmap.k": str(args.k), "sarmap.points_per_block": str(args.points),
                     "sarmap.training": json.dumps({"random_weights": True, "seed": args.seed,
                                                    "like": Path(args.like).name})})
    write_safetensors(args.out, tensors, metadata)
    print(f"wrote {args.out}: k {args.k}, emb {args.emb}, {args.points} points per block, random weights")


if __name__ == "__main__":
    main()
