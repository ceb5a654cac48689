"""sarmap.distributed on a two-worker LocalCluster: a sequence split in two,
mapped as two tasks and merged, keeps the whole sequence's points and knows
every voxel its map holds; a part that fails is reported and the others are
still merged; integrate_sequence maps a frame range; the example runs."""

import os
import subprocess
import sys

import numpy as np
import pytest

import sarmap
from conftest import FRAMES, LABELS_CONFIG

distributed = pytest.importorskip("distributed")
from sarmap.distributed import Part, map_sequences, split_sequence  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_a_frame_range_maps_those_frames_only(sequence_dir):
    sequence = sarmap.open_sequence(sequence_dir)
    mapper = sarmap.Mapper(LABELS_CONFIG, sensor=sequence.sensor)
    assert mapper.integrate_sequence(sequence, start=2, stop=5)["scans"] == 3
    assert mapper.scans == 3
    with pytest.raises(TypeError, match="stop"):
        mapper.integrate_sequence(sequence, stop="end")


def test_a_split_sequence_maps_on_two_workers_as_it_maps_whole(sequence_dir, module_mapper, client, tmp_path):
    parts = split_sequence(sequence_dir, 2)
    assert [(p.start, p.stop) for p in parts] == [(0, FRAMES // 2), (FRAMES // 2, FRAMES)]
    result = map_sequences(parts, config=LABELS_CONFIG, client=client)
    assert result.failed == {} and result.mapped == parts
    merged = result.mapper
    assert merged.merged and merged.scans == FRAMES
    centres, _ = module_mapper.occupied_voxels()
    assert np.all(merged.state_at(centres) != 0)
    merged.write(tmp_path / "merged")
    module_mapper.write(tmp_path / "whole")
    assert (tmp_path / "merged" / "semantic_points.ply").read_bytes() == \
        (tmp_path / "whole" / "semantic_points.ply").read_bytes()


def test_progress_shows_dasks_bar_and_maps_the_same(sequence_dir, client, capsys):
    result = map_sequences(split_sequence(sequence_dir, 2), config=LABELS_CONFIG, client=client, progress=True)
    assert result.failed == {} and result.mapper.scans == FRAMES
    assert "100%" in capsys.readouterr().out  # the text bar, completed


def test_a_failing_part_costs_only_itself(sequence_dir, client, tmp_path):
    missing = tmp_path / "no_such_sequence"
    parts = [Part(str(sequence_dir), 0, 3), Part(str(missing)), Part(str(sequence_dir), 3, None)]
    result = map_sequences(parts, config=LABELS_CONFIG, client=client)
    assert result.mapped == [parts[0], parts[2]]
    assert list(result.failed) == [str(missing)]
    assert "no_such_sequence" in result.failed[str(missing)]
    assert result.mapper.scans == FRAMES


def test_bad_arguments_say_which(sequence_dir):
    with pytest.raises(ValueError, match="parts"):
        split_sequence(sequence_dir, 0)
    with pytest.raises(TypeError, match="sequences"):
        map_sequences([42], client=object())
    with pytest.raises(ValueError, match="sequences"):
        map_sequences([], client=object())


def test_the_example_maps_merges_and_writes(sequence_dir, labels_config, tmp_path):
    example = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python", "dask_many_runs.py")
    out = tmp_path / "merged"
    result = subprocess.run([sys.executable, example, str(out), str(sequence_dir), "--parts", "2", "--workers", "1",
                             "--config", str(labels_config)], capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stderr
    assert f"2 parts ({FRAMES} scans) on 1 workers" in result.stdout
    assert (out / "manifest.json").exists() and (out / "map.sarmap").exists()
