"""Many sequences, or one sequence split among robots, mapped as tasks on a
Dask cluster and merged into one map (docs/python.md, "Many runs on Dask").

    from sarmap.distributed import map_sequences, split_sequence
    result = map_sequences(split_sequence("datasets/building", parts=4),
                           config={"classifier": {"kind": "geometric"}})
    result.mapper.write("out/building")

Each task opens its sequence on a worker, maps its frames with a Mapper
(whose native code releases the GIL) and returns the Mapper, which pickles
with its whole state; the Mappers are merged pairwise, in the order given, in
a tree of merge tasks, so no single worker merges them all. A task that fails
costs only its part: the others are merged and the failure is reported. The
workers read the sequences and the model from their own file systems.
"""

from dataclasses import dataclass, field
import os
import time

import sarmap


@dataclass(frozen=True)
class Part:
    """Frames [start, stop) of the sequence at `path` (stop None: to its end)."""

    path: str
    start: int = 0
    stop: int | None = None

    def __str__(self):
        if self.start == 0 and self.stop is None:
            return self.path
        return f"{self.path}[{self.start}:{'' if self.stop is None else self.stop}]"


@dataclass
class MapResult:
    """The merged Mapper (None when every part failed), the parts it holds,
    the parts that failed with their errors, and the wall time of the
    mapping tasks (until the last finished) and from then to the merged
    Mapper on the client (the merges and the Mappers' travel)."""

    mapper: "sarmap.Mapper | None"
    mapped: list = field(default_factory=list)
    failed: dict = field(default_factory=dict)
    map_seconds: float = 0.0
    merge_seconds: float = 0.0


def split_sequence(path, parts):
    """`parts` consecutive Parts of one sequence, as robots sharing a building
    would map it (as equal in frames as they divide)."""
    if not isinstance(parts, int) or parts < 1:
        raise ValueError(f"parts: expected an integer >= 1, got {parts!r}")
    frames = len(sarmap.open_sequence(path))
    bounds = [frames * i // parts for i in range(parts + 1)]
    return [Part(os.fspath(path), bounds[i], bounds[i + 1]) for i in range(parts) if bounds[i] < bounds[i + 1]]


def local_cluster(workers=None):
    """A LocalCluster for sarmap: `workers` single-threaded worker processes
    (one per core by default), without the malloc trim threshold Dask's
    nanny sets in its workers' environment: glibc then also stops adapting
    its mmap threshold, every large buffer of a scan becomes a fresh mmap,
    and mapping takes about twice as long (PERF.md, "Many parts on Dask").
    A cluster of your own should drop it too
    (`distributed.nanny.pre-spawn-environ`)."""
    import dask
    from distributed import LocalCluster

    environ = dict(dask.config.get("distributed.nanny.pre-spawn-environ", default={}) or {})
    environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}):
        return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                            dashboard_address=None)


def _as_part(item):
    if isinstance(item, Part):
        return item
    if isinstance(item, (str, os.PathLike)):
        return Part(os.fspath(item))
    raise TypeError(f"sequences: expected paths or Parts, got {type(item).__name__}")


def _map_part(part, config, threads):
    if threads:
        sarmap.set_threads(threads)
    sequence = sarmap.open_sequence(part.path)
    mapper = sarmap.Mapper(config, sensor=sequence.sensor)
    mapper.integrate_sequence(sequence, start=part.start, stop=part.stop)
    mapper.finish()
    return mapper


def _merge_pair(first, second):
    first.merge(second)
    return first


def map_sequences(sequences, config=None, client=None, *, threads_per_task=0, progress=False):
    """Maps every item of `sequences` (paths or Parts) as one Dask task each
    and merges the results in a tree. client: a distributed.Client; None
    starts local_cluster() (one worker process per core, one task each) and
    closes it afterwards. config: a Mapper config (dict or path), the same
    for every part: maps merge only at one resolution. threads_per_task:
    sarmap.set_threads in each task (0: every core the worker has).
    progress: show Dask's progress bar. Returns a MapResult."""
    from distributed import Client, progress as show_progress, wait

    parts = [_as_part(item) for item in sequences]
    if not parts:
        raise ValueError("sequences: nothing to map")
    if isinstance(config, os.PathLike):
        config = os.fspath(config)
    own_client = client is None
    if own_client:
        cluster = local_cluster()
        client = Client(cluster)
    try:
        start = time.perf_counter()
        futures = [client.submit(_map_part, part, config, threads_per_task, pure=False) for part in parts]
        if progress:
            show_progress(futures)
        wait(futures)
        result = MapResult(mapper=None, map_seconds=time.perf_counter() - start)
        start = time.perf_counter()
        done = []
        for part, future in zip(parts, futures):
            if future.status == "finished":
                result.mapped.append(part)
                done.append(future)
            else:
                result.failed[str(part)] = f"{type(future.exception()).__name__}: {future.exception()}"
        # Pairwise, neighbours first, so that a part's earlier neighbour is
        # always the side merged into (the kept points of a split sequence
        # are then those of mapping it whole).
        while len(done) > 1:
            merged = [client.submit(_merge_pair, done[i], done[i + 1], pure=False) for i in range(0, len(done) - 1, 2)]
            if len(done) % 2:
                merged.append(done[-1])
            done = merged
        if done:
            result.mapper = done[0].result()
        result.merge_seconds = time.perf_counter() - start
        return result
    finally:
        if own_client:
            client.close()
            cluster.close()
