#!/usr/bin/python3
# sarmap's DGCNN against PyTorch on the same model and block, in one run:
# runs BM_DgcnnBlock of sarmap_semantic_bench and the PyTorch peer
# (dgcnn_torch.py, with the allocator settings that make torch fastest here)
# at each thread count, then prints both and the ratio; then kNN alone
# (BM_Knn, input order, and BM_KnnSpatialOrder, the network's order, of
# sarmap_kernels_bench against the reference's matmul + topk, whose time does
# not depend on the points).
#
#   /usr/bin/python3 bench/peers/dgcnn_side_by_side.py --bench build/release/bench/semantic/sarmap_semantic_bench \
#       --model datasets/models/ramps-dgcnn.safetensors --block BLOCK.npy
# Without --model/--block: a random full-size model and 4096-point block are made.
import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
PEER_ENV = {"MALLOC_MMAP_MAX_": "0", "MALLOC_TRIM_THRESHOLD_": "68719476736"}


def sarmap_ms(bench, model, block, threads, simd):
    env = dict(os.environ, SARMAP_DGCNN_MODEL=model, SARMAP_DGCNN_BLOCK=block)
    out = subprocess.run([bench, f"--benchmark_filter=BM_DgcnnBlock/{simd}/threads:{threads}/",
                          "--benchmark_format=json", "--benchmark_min_time=1"],
                         env=env, check=True, capture_output=True, text=True).stdout
    runs = [b for b in json.loads(out)["benchmarks"] if b.get("run_type") == "iteration"]
    if not runs:
        raise SystemExit(f"no BM_DgcnnBlock/{simd}/threads:{threads} result (is {simd} supported here?)")
    return runs[0]["real_time"]  # the benchmark reports milliseconds


def sarmap_knn_ms(bench, name, dim, threads, simd):
    out = subprocess.run([bench, f"--benchmark_filter={name}/{simd}/dim:{dim}/threads:{threads}/",
                          "--benchmark_format=json", "--benchmark_min_time=0.5"],
                         check=True, capture_output=True, text=True).stdout
    runs = [b for b in json.loads(out)["benchmarks"] if b.get("run_type") == "iteration"]
    if not runs:
        raise SystemExit(f"no {name}/{simd}/dim:{dim}/threads:{threads} result")
    return runs[0]["real_time"]


def blas_thread_choices(threads):
    """OpenBLAS threads to try for the peer at THREADS torch threads: OpenBLAS
    starts one thread per core unless told otherwise, which at 1 torch thread
    would hand the peer a second core, and at 2 it fights torch's own pool
    (measured here: 2 torch threads ran fastest with 1 OpenBLAS thread). The
    peer gets the best of the settings that use no more than THREADS cores."""
    return sorted({1, threads})


def run_peer(args, threads):
    """Runs dgcnn_torch.py with each OpenBLAS thread count; returns the fastest result."""
    best = None
    for blas_threads in blas_thread_choices(threads):
        env = dict(os.environ, **PEER_ENV, OPENBLAS_NUM_THREADS=str(blas_threads))
        out = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "dgcnn_torch.py"), *args,
                              "--threads", str(threads), "--repeat", "9"],
                             env=env, check=True, capture_output=True, text=True).stdout
        result = dict(json.loads(out.strip().splitlines()[-1]), openblas_threads=blas_threads)
        key = "ms" if "ms" in result else "ms_per_block"
        if best is None or result[key] < best[key]:
            best = result
    return best


def torch_knn_ms(dim, threads):
    return run_peer(["--knn", str(dim), "--points", "4096", "--k", "20"], threads)["ms"]


def torch_run(model, block, threads):
    return run_peer([model, block], threads)


def main(argv):
    parser = argparse.ArgumentParser(description="sarmap vs PyTorch DGCNN, side by side")
    parser.add_argument("--bench", default=os.path.join(ROOT, "build/release/bench/semantic/sarmap_semantic_bench"))
    parser.add_argument("--model")
    parser.add_argument("--block")
    parser.add_argument("--simd", default="avx512", help="sarmap's instruction set: sse4_2, avx2 or avx512")
    parser.add_argument("--threads", default="1,2")
    parser.add_argument("--knn-bench", default=os.path.join(ROOT, "build/release/bench/kernels/sarmap_kernels_bench"),
                        help="also compare kNN alone (4096 points, k 20) with this benchmark; '' skips it")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        model, block = args.model, args.block
        if not model or not block:
            model, block = os.path.join(tmp, "model.safetensors"), os.path.join(tmp, "block.npy")
            subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tools/python/dgcnn_reference.py"), "random-model",
                            model, "--block", block], check=True)
        print(f"model {args.model or 'random full-size'}, block {args.block or 'synthetic 4096 points'}")
        print("| threads | sarmap ms/block | PyTorch ms/block | speed-up | PyTorch BLAS (threads) |")
        print("|---|---|---|---|---|")
        for threads in (int(t) for t in args.threads.split(",")):
            ours = sarmap_ms(args.bench, model, block, threads, args.simd)
            peer = torch_run(model, block, threads)
            print(f"| {threads} | {ours:.1f} | {peer['ms_per_block']:.1f} | {peer['ms_per_block'] / ours:.1f}x | "
                  f"{', '.join(peer['blas']) or 'none found'} ({peer['openblas_threads']}) |", flush=True)
    if args.knn_bench:
        print("\nkNN alone, 4096 points, k 20 (PyTorch: matmul distances + topk, as the reference). sarmap in input")
        print("order on random points, and in the network's spatial order (order computed inside the timing) on")
        print("a random 3-D cloud and on 64-d features that vary smoothly with its positions:")
        print("| dim | threads | sarmap input order ms | sarmap spatial order ms | PyTorch ms | speed-up (input, spatial) |")
        print("|---|---|---|---|---|---|")
        for dim in (3, 64):
            for threads in (int(t) for t in args.threads.split(",")):
                plain = sarmap_knn_ms(args.knn_bench, "BM_Knn", dim, threads, args.simd)
                ordered = sarmap_knn_ms(args.knn_bench, "BM_KnnSpatialOrder", dim, threads, args.simd)
                peer = torch_knn_ms(dim, threads)
                print(f"| {dim} | {threads} | {plain:.1f} | {ordered:.1f} | {peer:.1f} | "
                      f"{peer / plain:.1f}x, {peer / ordered:.1f}x |", flush=True)

if __name__ == "__main__":
    main(sys.argv[1:])
