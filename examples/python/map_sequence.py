"""Maps a scan sequence with sarmap's Python module and writes the run's
folder, as `sarmap run SEQUENCE --out OUT [--config CONFIG]` does.

usage: python3 map_sequence.py SEQUENCE OUT [CONFIG]
(CONFIG: a config file; without one, the shipped DGCNN classifies the points.)
"""
import sys

import sarmap

sequence_path, out = sys.argv[1], sys.argv[2]
config = sys.argv[3] if len(sys.argv) > 3 else None
sequence = sarmap.open_sequence(sequence_path)
mapper = sarmap.Mapper(config, sensor=sequence.sensor)
for points, pose, origin in sequence:  # world-frame points, as the sequence's reader gives them
    mapper.integrate(points, pose, frame="world", origin=origin)
mapper.finish()
mapper.write(out, input=sequence)
centres, classes = mapper.occupied_voxels()
print(f"{mapper.scans} scans: {len(centres)} occupied voxels, {len(mapper.segments()['segments'])} segments, "
      f"{len(mapper.graph()['nodes'])} graph nodes; wrote {out}")
