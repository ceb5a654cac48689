"""Maps sequences, or one sequence split among robots, on a Dask cluster with
sarmap.distributed, merges the maps and writes the merged run's folder.

usage: python3 dask_many_runs.py OUT SEQUENCE [SEQUENCE ...] [--parts N]
       [--workers W | --scheduler ADDRESS] [--config CONFIG]
(--parts splits each sequence among N robots; --workers starts a LocalCluster
of W single-threaded worker processes, one per core by default; --scheduler
uses a running cluster, whose workers must reach the sequences' paths.)
"""
import argparse
import os

import distributed

from sarmap.distributed import Part, local_cluster, map_sequences, split_sequence


def main():
    # Worker processes start by importing this file again: the work runs
    # only in the main process.
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("sequences", nargs="+")
    parser.add_argument("--parts", type=int, default=1)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--scheduler")
    parser.add_argument("--config")
    args = parser.parse_args()

    parts = [p for s in args.sequences for p in (split_sequence(s, args.parts) if args.parts > 1 else [Part(s)])]
    if args.scheduler:
        client = distributed.Client(args.scheduler)
    else:
        client = distributed.Client(local_cluster(args.workers))
    with client:
        workers = len(client.scheduler_info()["workers"])
        result = map_sequences(parts, config=args.config, client=client)
    for part, error in result.failed.items():
        print(f"failed: {part}: {error}")
    if result.mapper is None:
        raise SystemExit("every part failed")
    result.mapper.write(args.out)
    print(f"{len(result.mapped)} parts ({result.mapper.scans} scans) on {workers} workers: mapped in "
          f"{result.map_seconds:.2f} s ({60 * len(result.mapped) / result.map_seconds:.1f} parts/min), merged in "
          f"{result.merge_seconds:.2f} s; wrote {args.out}")


if __name__ == "__main__":
    main()
