"""read_cloud / write_cloud against the files the sarmap binary reads: what the
module writes, `sarmap info` describes, and what it reads, it reads whole."""

import json

import numpy as np
import pytest

import sarmap
from conftest import run_cli


def cloud_arrays(n=500):
    rng = np.random.default_rng(11)
    points = rng.uniform(-5, 5, (n, 3)).astype(np.float32)
    labels = rng.integers(0, 6, n).astype(np.uint8)
    colors = rng.integers(0, 256, (n, 3)).astype(np.uint8)
    intensity = rng.uniform(0, 1, n).astype(np.float32)
    scores = {"wall": rng.uniform(0, 1, n).astype(np.float32)}
    return points, labels, colors, intensity, scores


@pytest.mark.parametrize("name,options", [("c.ply", {}), ("c.ply", {"binary": False}), ("c.pcd", {}),
                                          ("c.pcd", {"compressed": True})])
def test_round_trip(tmp_path, name, options):
    points, labels, colors, intensity, scores = cloud_arrays()
    path = tmp_path / name
    sarmap.write_cloud(path, points, labels=labels, colors=colors, intensity=intensity, scores=scores, **options)
    cloud = sarmap.read_cloud(path)
    assert len(cloud) == 500
    tolerance = 1e-6 if options.get("binary", True) else 1e-5
    np.testing.assert_allclose(cloud.xyz, points, rtol=tolerance)
    np.testing.assert_array_equal(cloud.labels, labels)
    np.testing.assert_array_equal(cloud.colors, colors)
    np.testing.assert_allclose(cloud.intensity, intensity, rtol=tolerance)
    np.testing.assert_allclose(cloud.scores["wall"], scores["wall"], rtol=tolerance)
    info = json.loads(run_cli("info", path, "--json").stdout)
    assert info["points"] == 500


def test_write_cloud_takes_a_cloud_or_arrays_not_both(tmp_path):
    points, labels, *_ = cloud_arrays()
    cloud = sarmap.PointCloud(points, labels=labels)
    with pytest.raises(TypeError, match="^points: a PointCloud carries its own fields"):
        sarmap.write_cloud(tmp_path / "c.ply", cloud, labels=labels)
    with pytest.raises(TypeError, match="^colors: "):
        sarmap.write_cloud(tmp_path / "c.ply", points, colors=np.zeros((500, 3)))
    with pytest.raises(ValueError, match=r"^intensity: expected shape \(500,\)"):
        sarmap.write_cloud(tmp_path / "c.ply", points, intensity=np.zeros(3, np.float32))


def test_sequence_frames_are_the_files(sequence_dir):
    sequence = sarmap.open_sequence(sequence_dir)
    manifest = json.loads((sequence_dir / "sequence.json").read_text())
    assert len(sequence) == len(manifest["frames"]) == 6
    assert sequence.layout == "sarmap" and sequence.sensor["type"] == "depth_camera"
    assert sequence.arena_sha256 == manifest["arena_sha256"]
    scans = list(sequence)
    assert [s.index for s in scans] == list(range(6))
    for scan, frame in zip(scans, manifest["frames"]):
        points, pose, origin = scan
        np.testing.assert_array_equal(pose.reshape(-1), frame["pose"])
        np.testing.assert_array_equal(origin, frame.get("origin", pose[:3, 3]))
        # Simulated frames are in the world frame: the file's points as they are.
        on_disk = sarmap.read_cloud(sequence_dir / frame["file"])
        np.testing.assert_array_equal(points.xyz, on_disk.xyz)
        np.testing.assert_array_equal(points.labels, on_disk.labels)
        assert scan.source.endswith(frame["file"])
    # A second pass starts again from the first frame.
    assert next(iter(sequence)).index == 0
