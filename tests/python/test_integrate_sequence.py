"""Mapper.integrate_sequence against `sarmap run`, overlapped and in order, a
damaged frame costing only itself, and the thread setting."""

import json
import shutil

import pytest

import sarmap
from conftest import FRAMES, run_cli
from test_mapper_matches_cli import MAP_OUTPUTS


@pytest.mark.parametrize("overlap", [True, False])
def test_a_sequence_maps_as_the_cli_maps_it(sequence_dir, labels_config, cli_run, tmp_path, overlap):
    sequence = sarmap.open_sequence(sequence_dir)
    mapper = sarmap.Mapper(labels_config, sensor=sequence.sensor)
    result = mapper.integrate_sequence(sequence, overlap=overlap)
    assert result == {"scans": FRAMES, "skipped": []}
    assert mapper.scans == FRAMES
    mapper.finish()
    out = tmp_path / "run"
    mapper.write(out, input=sequence)
    for name in MAP_OUTPUTS:
        assert (out / name).read_bytes() == (cli_run / name).read_bytes(), name


def test_a_damaged_frame_costs_only_itself(sequence_dir, labels_config, tmp_path):
    damaged = tmp_path / "damaged"
    shutil.copytree(sequence_dir, damaged)
    frames = json.loads((damaged / "sequence.json").read_text())["frames"]
    bad = damaged / frames[2]["file"]
    bad.write_bytes(bad.read_bytes()[:200])  # cut inside the points
    cli = tmp_path / "cli"
    run_cli("run", damaged, "--config", labels_config, "--out", cli, "--quiet")

    sequence = sarmap.open_sequence(damaged)
    mapper = sarmap.Mapper(labels_config, sensor=sequence.sensor)
    result = mapper.integrate_sequence(sequence)
    assert result["scans"] == FRAMES - 1
    [skipped] = result["skipped"]
    assert skipped["frame"] == 2 and frames[2]["file"] in skipped["error"], skipped
    mapper.finish()
    out = tmp_path / "module"
    mapper.write(out, input=sequence)
    assert (out / "map.sarmap").read_bytes() == (cli / "map.sarmap").read_bytes()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scans_skipped"] == 1


def test_integrate_sequence_takes_a_sequence_only():
    mapper = sarmap.Mapper({"classifier": {"kind": "labels"}})
    with pytest.raises(TypeError):
        mapper.integrate_sequence("not a sequence")


def test_the_thread_limit_changes_the_time_not_the_map(sequence_dir, labels_config, cli_run, tmp_path):
    cores = sarmap.threads()
    assert cores >= 1
    try:
        sarmap.set_threads(1)
        assert sarmap.threads() == 1
        sequence = sarmap.open_sequence(sequence_dir)
        mapper = sarmap.Mapper(labels_config, sensor=sequence.sensor)
        mapper.integrate_sequence(sequence)
        mapper.finish()
        out = tmp_path / "one_thread"
        mapper.write(out)
        assert (out / "map.sarmap").read_bytes() == (cli_run / "map.sarmap").read_bytes()
    finally:
        sarmap.set_threads(0)
    assert sarmap.threads() == cores
    with pytest.raises(ValueError, match="threads"):
        sarmap.set_threads(-1)
    with pytest.raises(TypeError, match="threads"):
        sarmap.set_threads(1.5)
