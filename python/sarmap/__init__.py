"""sarmap: semantic, metric and topological maps of search-and-rescue arenas
from posed point clouds, on the CPU (docs/python.md).

    import sarmap
    sequence = sarmap.open_sequence("datasets/my_sequence")
    mapper = sarmap.Mapper({"classifier": {"kind": "geometric"}}, sensor=sequence.sensor)
    for points, pose, origin in sequence:
        mapper.integrate(points, pose, frame="world", origin=origin)
    mapper.finish()
    mapper.write("out/my_run", input=sequence)

The classes and functions are the C++ library's (the _sarmap extension); this
file adds where the shipped data is found.
"""

from ._sarmap import (
    CLASS_NAMES,
    FREE,
    OCCUPIED,
    UNKNOWN,
    Mapper,
    PointCloud,
    Sequence,
    __version__,
    classify,
    open_sequence,
    read_cloud,
    set_threads,
    threads,
    write_cloud,
)
from ._data import data_dirs, shipped_arena, shipped_model
from ._scan import Scan

__all__ = [
    "CLASS_NAMES", "FREE", "OCCUPIED", "UNKNOWN", "Mapper", "PointCloud", "Scan", "Sequence", "__version__",
    "classify", "data_dirs", "open_sequence", "read_cloud", "set_threads", "shipped_arena", "shipped_model",
    "threads", "write_cloud",
]
