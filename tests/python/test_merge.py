"""Mapper.merge: a sequence mapped in two halves and merged gives the whole
sequence's map (the kept points exactly, every voxel the whole map knows is
known); a merged Mapper takes no more scans; Mappers that cannot merge raise
ValueError naming the setting. Pickling: a Mapper continues after a round
trip as the original does, a merged one stays merged, a damaged pickle is a
ValueError."""

import pickle

import numpy as np
import pytest

import sarmap
from conftest import FRAMES, LABELS_CONFIG


def mapped(sequence_dir, frames, config=LABELS_CONFIG):
    sequence = sarmap.open_sequence(sequence_dir)
    mapper = sarmap.Mapper(config, sensor=sequence.sensor)
    for index, (points, pose, origin) in enumerate(sequence):
        if index in frames:
            mapper.integrate(points, pose, frame="world", origin=origin)
    mapper.finish()
    return mapper


def test_two_halves_merged_give_the_whole_sequences_map(sequence_dir, module_mapper, tmp_path):
    half = FRAMES // 2
    first = mapped(sequence_dir, range(0, half))
    second = mapped(sequence_dir, range(half, FRAMES))
    counts = first.merge(second)
    assert first.merged and not second.merged
    assert counts["blocks_merged"] > 0 and counts["semantic_points_added"] > 0
    assert counts["graph_nodes"] > 0
    assert first.scans == FRAMES

    centres, classes = module_mapper.occupied_voxels()
    assert np.all(first.state_at(centres) != 0)  # every voxel the whole map holds is known
    first.write(tmp_path / "merged")
    whole = tmp_path / "whole"
    module_mapper.write(whole)
    # A voxel keeps its first point, and the first half came first.
    merged_points = (tmp_path / "merged" / "semantic_points.ply").read_bytes()
    assert merged_points == (whole / "semantic_points.ply").read_bytes()

    with pytest.raises(ValueError, match="merged Mapper takes no more scans"):
        points, pose, origin = next(iter(sarmap.open_sequence(sequence_dir)))
        first.integrate(points, pose, frame="world", origin=origin)


def test_mappers_that_cannot_merge_say_why(sequence_dir):
    first = mapped(sequence_dir, range(0, 2))
    coarse = mapped(sequence_dir, range(2, 4), {**LABELS_CONFIG, "voxel": 0.1})
    with pytest.raises(ValueError, match="resolution"):
        first.merge(coarse)
    with pytest.raises(ValueError, match="other"):
        first.merge(first)
    assert not first.merged


def test_a_pickled_mapper_continues_as_the_original_would(sequence_dir, tmp_path):
    """What sarmap's Mappers need to travel between processes (Dask workers)."""
    frames = list(sarmap.open_sequence(sequence_dir))
    original = sarmap.Mapper(LABELS_CONFIG)
    for points, pose, origin in frames[:3]:
        original.integrate(points, pose, frame="world", origin=origin)
    copy = pickle.loads(pickle.dumps(original))
    assert copy.scans == 3 and not copy.merged
    for mapper in (original, copy):
        for points, pose, origin in frames[3:]:
            mapper.integrate(points, pose, frame="world", origin=origin)
        mapper.finish()
    original.write(tmp_path / "original")
    copy.write(tmp_path / "copy")
    for name in ("map.sarmap", "segments.json", "graph.json", "semantic_points.ply"):
        assert (tmp_path / "copy" / name).read_bytes() == (tmp_path / "original" / name).read_bytes(), name


def test_a_merged_mapper_pickles_as_a_merged_one(sequence_dir):
    first = mapped(sequence_dir, range(0, 2))
    first.merge(mapped(sequence_dir, range(2, 4)))
    copy = pickle.loads(pickle.dumps(first))
    assert copy.merged and copy.scans == 4
    centres, _ = first.occupied_voxels()
    assert np.array_equal(copy.state_at(centres), first.state_at(centres))


def test_a_damaged_pickle_is_a_value_error(sequence_dir):
    version, config, sensor, state, offered, dropped = mapped(sequence_dir, range(0, 2)).__getstate__()
    with pytest.raises(ValueError, match="pickled Mapper"):
        truncated = state[: len(state) // 2]
        sarmap.Mapper.__new__(sarmap.Mapper).__setstate__((version, config, sensor, truncated, offered, dropped))
    with pytest.raises(ValueError, match="state"):
        sarmap.Mapper.__new__(sarmap.Mapper).__setstate__((99, config, sensor, state, offered, dropped))


def test_a_transform_carries_the_other_map_into_this_frame(sequence_dir):
    source = mapped(sequence_dir, range(0, 2))
    turn = np.array([[0, -1, 0, 3.0], [1, 0, 0, -2.0], [0, 0, 1, 0.5], [0, 0, 0, 1]])
    merged = sarmap.Mapper(LABELS_CONFIG, sensor=sarmap.open_sequence(sequence_dir).sensor)
    merged.merge(source, transform=turn)
    centres, classes = source.occupied_voxels()
    moved = centres @ turn[:3, :3].T + turn[:3, 3]
    assert np.all(merged.state_at(moved) == 2)
    assert np.array_equal(merged.class_at(moved), source.class_at(centres))
    with pytest.raises(ValueError, match="transform"):
        merged.merge(mapped(sequence_dir, range(2, 3)), transform=np.eye(3))


def test_a_written_state_loads_into_the_same_mapper(sequence_dir, tmp_path):
    source = mapped(sequence_dir, range(0, 3))
    source.write(tmp_path / "run", keep_state=True)
    loaded = sarmap.Mapper.load(tmp_path / "run" / "mapper.state")
    centres, classes = source.occupied_voxels()
    assert np.array_equal(loaded.state_at(centres), source.state_at(centres))
    assert loaded.scans == source.scans
    loaded.write(tmp_path / "again")
    for name in ["map.sarmap", "semantic_points.ply", "segments.json", "graph.json"]:
        assert (tmp_path / "again" / name).read_bytes() == (tmp_path / "run" / name).read_bytes(), name
    (tmp_path / "damaged.state").write_bytes(b"SARMAPMF" + b"\0" * 80)
    with pytest.raises(ValueError, match="damaged"):
        sarmap.Mapper.load(tmp_path / "damaged.state")
    with pytest.raises(OSError):
        sarmap.Mapper.load(tmp_path / "missing.state")
