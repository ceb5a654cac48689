#!/usr/bin/python3
# The PyTorch peer of sarmap's DGCNN benchmark: the reference network
# (tools/python/dgcnn_reference.py, the DGCNN_semseg layout) on the same
# .safetensors model and the same (N, C) block, in inference mode with a
# matched thread count. Prints one JSON line: ms per block and which BLAS
# library torch actually loaded (Debian's torch runs on whatever
# libblas.so.3 the alternatives system points at).
#
#   /usr/bin/python3 bench/peers/dgcnn_torch.py MODEL.safetensors BLOCK.npy --threads 1
import argparse
import json
import os
import sys
import time

import numpy as np
import torch

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "python"))
from dgcnn_reference import model_from_tensors  # noqa: E402
from export_safetensors import read_safetensors  # noqa: E402


def loaded_blas():
    """The BLAS shared object mapped into this process, e.g. .../openblas-pthread/libblas.so.3."""
    with open("/proc/self/maps") as f:
        paths = {line.split()[-1] for line in f if "blas" in line.lower() and "/" in line}
    return sorted(paths)


def main(argv):
    parser = argparse.ArgumentParser(description="time the PyTorch DGCNN on one block")
    parser.add_argument("model")
    parser.add_argument("block")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    torch.set_num_threads(args.threads)
    tensors, metadata = read_safetensors(args.model)
    model = model_from_tensors(tensors, int(metadata.get("sarmap.k", 20)))
    x = torch.from_numpy(np.load(args.block).T[None].copy())
    with torch.inference_mode():
        model(x)  # warm-up: first-call allocations and thread start
        times = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            model(x)
            times.append(time.perf_counter() - start)
    print(json.dumps({"peer": "pytorch", "torch": torch.__version__, "threads": args.threads,
                      "points": x.shape[2], "ms_per_block": 1000 * float(np.median(times)),
                      "blas": loaded_blas(),
                      "malloc_env": {k: os.environ.get(k) for k in ("MALLOC_MMAP_MAX_", "MALLOC_TRIM_THRESHOLD_")}}))


if __name__ == "__main__":
    main(sys.argv[1:])
