#!/usr/bin/python3
# The PyTorch peer of sarmap's DGCNN benchmark: the reference network
# (tools/python/dgcnn_reference.py, the DGCNN_semseg layout) on the same
# .safetensors model and the same (N, C) block, in inference mode with a
# matched thread count. Prints one JSON line: ms per block and which BLAS
# library torch actually loaded (Debian's torch runs on whatever
# libblas.so.3 the alternatives system points at).
#
#   /usr/bin/python3 bench/peers/dgcnn_torch.py MODEL.safetensors BLOCK.npy --threads 1
#   /usr/bin/python3 bench/peers/dgcnn_torch.py --knn 64 --points 4096 --k 20 --threads 1
# The second form times the reference's kNN alone (pairwise distances by
# matmul, then topk) on random points, the peer of sarmap's BM_Knn.
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


def reference_knn(x, k):
    """The reference implementation's kNN: x is (1, dim, N); returns (1, N, k) indices."""
    inner = -2 * torch.matmul(x.transpose(2, 1), x)
    xx = torch.sum(x**2, dim=1, keepdim=True)
    return (-xx - inner - xx.transpose(2, 1)).topk(k=k, dim=-1)[1]


def median_ms(fn, repeat):
    with torch.inference_mode():
        fn()  # warm-up: first-call allocations and thread start
        times = []
        for _ in range(repeat):
            start = time.perf_counter()
            fn()
            times.append(time.perf_counter() - start)
    return 1000 * float(np.median(times))


def main(argv):
    parser = argparse.ArgumentParser(description="time the PyTorch DGCNN on one block, or its kNN alone")
    parser.add_argument("model", nargs="?")
    parser.add_argument("block", nargs="?")
    parser.add_argument("--knn", type=int, metavar="DIM", help="time only the kNN on random DIM-d points")
    parser.add_argument("--points", type=int, default=4096)
    parser.add_argument("--k", type=int, default=20)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    torch.set_num_threads(args.threads)
    if args.knn:
        x = torch.from_numpy(np.random.default_rng(1).standard_normal((1, args.knn, args.points), dtype=np.float32))
        print(json.dumps({"peer": "pytorch-knn", "torch": torch.__version__, "threads": args.threads,
                          "dim": args.knn, "points": args.points, "k": args.k,
                          "ms": median_ms(lambda: reference_knn(x, args.k), args.repeat), "blas": loaded_blas()}))
        return
    if not args.model or not args.block:
        parser.error("MODEL and BLOCK are required (or --knn DIM)")
    tensors, metadata = read_safetensors(args.model)
    model = model_from_tensors(tensors, int(metadata.get("sarmap.k", 20)))
    x = torch.from_numpy(np.load(args.block).T[None].copy())
    ms = median_ms(lambda: model(x), args.repeat)
    print(json.dumps({"peer": "pytorch", "torch": torch.__version__, "threads": args.threads,
                      "points": x.shape[2], "ms_per_block": ms,
                      "blas": loaded_blas(),
                      "malloc_env": {k: os.environ.get(k) for k in ("MALLOC_MMAP_MAX_", "MALLOC_TRIM_THRESHOLD_")}}))


if __name__ == "__main__":
    main(sys.argv[1:])
