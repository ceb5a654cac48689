"""The module's Mapper against `sarmap run` on the same sequence: the same run
API, so the same maps, byte for byte."""

import json
import subprocess

import numpy as np
import pytest

import sarmap
from conftest import cli_path, run_cli

# The outputs that depend on the maps alone (the manifest, profile and summary
# also record paths and times).
MAP_OUTPUTS = ["map.sarmap", "voxels.ply", "segments.json", "graph.json", "grid.pgm"]


def test_run_folder_matches_the_cli(module_mapper, cli_run, sequence_dir, tmp_path):
    out = tmp_path / "run"
    module_mapper.write(out, input=sarmap.open_sequence(sequence_dir))
    for name in MAP_OUTPUTS:
        assert (out / name).read_bytes() == (cli_run / name).read_bytes(), name
    manifest = json.loads((out / "manifest.json").read_text())
    cli_manifest = json.loads((cli_run / "manifest.json").read_text())
    assert manifest["input"] == cli_manifest["input"]
    assert manifest["layout"] == "sarmap"
    assert manifest["arena_sha256"] == cli_manifest["arena_sha256"]
    assert manifest["scans"] == cli_manifest["scans"] == module_mapper.scans == 6
    # The folder is a whole run the CLI's readers take.
    run_cli("info", out / "map.sarmap")


def test_sensor_frame_points_map_as_a_sensor_frame_sequence(sequence_dir, tmp_path):
    """frame="sensor": the same float32 sensor-frame points the CLI reads from a
    points_frame "sensor" sequence give the same map."""
    sequence = sarmap.open_sequence(sequence_dir)
    folder = tmp_path / "sensor_sequence"
    folder.mkdir()
    frames, scans = [], []
    for scan in sequence:
        pose = scan.pose
        world = scan.points.xyz.astype(np.float64)
        sensor = ((world - pose[:3, 3]) @ pose[:3, :3]).astype(np.float32)
        name = f"frame_{scan.index:06d}.ply"
        sarmap.write_cloud(folder / name, sensor, labels=scan.points.labels)
        frames.append({"file": name, "pose": pose.reshape(-1).tolist()})
        scans.append((sensor, pose, scan.points.labels.copy()))
    sensor_block = json.loads((sequence_dir / "sequence.json").read_text())["sensor"]
    (folder / "sequence.json").write_text(json.dumps(
        {"version": 1, "points_frame": "sensor", "sensor": sensor_block, "frames": frames}))
    cli = tmp_path / "cli"
    run_cli("run", folder, "--classifier", "labels", "--out", cli, "--quiet")

    mapper = sarmap.Mapper({"classifier": {"kind": "labels"}}, sensor=sequence.sensor)
    for sensor, pose, labels in scans:
        mapper.integrate(sensor, pose, labels=labels)  # frame="sensor" is the default
    mapper.finish()
    out = tmp_path / "module"
    mapper.write(out)
    assert (out / "map.sarmap").read_bytes() == (cli / "map.sarmap").read_bytes()
    assert json.loads((out / "manifest.json").read_text())["layout"] == "arrays"


def test_occupied_voxels_are_the_cli_voxels(module_mapper, cli_run):
    centres, classes = module_mapper.occupied_voxels()
    voxels = sarmap.read_cloud(cli_run / "voxels.ply")
    assert centres.dtype == np.float32 and centres.shape == (len(voxels), 3)
    assert classes.dtype == np.uint8
    np.testing.assert_array_equal(centres, voxels.xyz)
    np.testing.assert_array_equal(classes, voxels.labels)
    assert module_mapper.counts()["occupied"] == len(voxels) > 1000


def test_queries_agree_with_the_voxels(module_mapper, cli_run, sequence_dir):
    voxels = sarmap.read_cloud(cli_run / "voxels.ply")
    centres = voxels.xyz
    assert (module_mapper.state_at(centres) == sarmap.OCCUPIED).all()
    np.testing.assert_array_equal(module_mapper.class_at(centres), voxels.labels)
    np.testing.assert_allclose(module_mapper.probability_at(centres), voxels.scores["probability"], rtol=1e-6)
    # float64 queries, and any leading shape.
    grid = centres.astype(np.float64).reshape(-1, 1, 3)
    assert module_mapper.state_at(grid).shape == (len(centres), 1)
    # Far outside the arena nothing is known.
    far = np.array([[500.0, 500.0, 500.0], [np.nan, 0, 0]])
    np.testing.assert_array_equal(module_mapper.state_at(far), [sarmap.UNKNOWN, sarmap.UNKNOWN])
    np.testing.assert_array_equal(module_mapper.probability_at(far), [0.5, 0.5])
    # Every ray starts in free space: the sensor's positions.
    origins = np.array([origin for _, _, origin in sarmap.open_sequence(sequence_dir)])
    assert (module_mapper.state_at(origins) == sarmap.FREE).all()
    assert (module_mapper.class_at(origins) == 0).all()


def test_segments_and_graph_are_the_cli_files(module_mapper, cli_run):
    assert module_mapper.segments() == json.loads((cli_run / "segments.json").read_text())
    graph = module_mapper.graph()
    assert graph == json.loads((cli_run / "graph.json").read_text())
    assert len(graph["nodes"]) > 0 and len(module_mapper.segments()["segments"]) > 0


def test_plan_matches_sarmap_plan(module_mapper, cli_run, tmp_path):
    nodes = module_mapper.graph()["nodes"]
    start, goal = nodes[0]["pos"], nodes[-1]["pos"]
    for graph in ["tree", "roadmap", "grid"]:
        path = tmp_path / f"{graph}.json"
        run_cli("plan", cli_run, "--from", ",".join(map(repr, start)), "--to", ",".join(map(repr, goal)),
                "--graph", graph, "--out", path, "--quiet")
        expected = json.loads(path.read_text())
        route = module_mapper.plan(start, goal, graph=graph)
        assert route["found"] == expected["found"]
        assert route["graph"] == expected["graph"] and route["algorithm"] == expected["algorithm"]
        if expected["found"]:
            np.testing.assert_allclose(route["points"], expected["points"], rtol=0, atol=1e-9)
            assert abs(route["length"] - expected["length"]) < 1e-9
            assert route["nodes"] == expected.get("nodes", [])


def test_the_binary_reads_the_module_runs(module_mapper, cli_run, sequence_dir, tmp_path):
    """eval scores the module's run as the binary's (the manifest names the
    sequence and its arena), and view draws a run of arrays, which names none."""
    out = tmp_path / "run"
    module_mapper.write(out, input=str(sequence_dir))
    arena = sarmap.shipped_arena()
    scores = [json.loads(run_cli("eval", "--arena", arena, "--run", run, "--json").stdout) for run in (out, cli_run)]
    for s in scores:
        del s["run"]
    assert scores[0] == scores[1]

    arrays = sarmap.Mapper({"classifier": {"kind": "labels"}})
    for points, pose, origin in sarmap.open_sequence(sequence_dir):
        arrays.integrate(points.xyz, pose, labels=points.labels, frame="world", origin=origin)
    arrays.finish()
    arrays.write(tmp_path / "arrays")
    result = subprocess.run([cli_path(), "view", str(tmp_path / "arrays")], capture_output=True, text=True)
    if result.returncode != 0 and "viewer.js" in result.stderr:
        pytest.skip("this build has no viewer script (web/node_modules missing)")
    assert result.returncode == 0, result.stderr
    assert "no trajectory" in result.stdout + result.stderr
    assert (tmp_path / "arrays" / "view.html").is_file()
