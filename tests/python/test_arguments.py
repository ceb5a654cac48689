"""Wrong arguments are TypeErrors (wrong type or dtype) or ValueErrors (wrong
shape or value) that name the argument, never a crash, and a refused scan
leaves the map as it was."""

import math

import numpy as np
import pytest

import sarmap

LABELS = {"classifier": {"kind": "labels"}}


def pose_at(x=0.0, y=0.0, z=0.5, yaw=0.0):
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, z], [0, 0, 0, 1]], dtype=np.float64)


def wall(n=400):
    """A small wall 2 m in front of the sensor (x forward), labelled wall."""
    rng = np.random.default_rng(7)
    points = np.column_stack([np.full(n, 2.0), rng.uniform(-1, 1, n), rng.uniform(-0.5, 0.5, n)]).astype(np.float32)
    return points, np.full(n, 2, dtype=np.uint8)


@pytest.fixture
def mapper():
    return sarmap.Mapper(LABELS)


def test_points_must_be_float32_n_by_3(mapper):
    points, labels = wall()
    with pytest.raises(TypeError, match=r"^points: .*float64"):
        mapper.integrate(points.astype(np.float64), pose_at(), labels=labels)
    with pytest.raises(TypeError, match=r"^points: .*list"):
        mapper.integrate(points.tolist(), pose_at(), labels=labels)
    with pytest.raises(ValueError, match=r"^points: expected shape \(N, 3\), got \(400, 2\)"):
        mapper.integrate(np.ascontiguousarray(points[:, :2]), pose_at(), labels=labels)
    assert mapper.scans == 0


def test_labels_must_be_uint8_class_ids_one_per_point(mapper):
    points, labels = wall()
    with pytest.raises(TypeError, match=r"^labels: .*int64"):
        mapper.integrate(points, pose_at(), labels=labels.astype(np.int64))
    with pytest.raises(ValueError, match=r"^labels: expected shape \(400,\)"):
        mapper.integrate(points, pose_at(), labels=labels[:10])
    bad = labels.copy()
    bad[17] = 6
    with pytest.raises(ValueError, match=r"^labels: point 17 has class 6"):
        mapper.integrate(points, pose_at(), labels=bad)
    # The labels classifier needs labels.
    with pytest.raises(ValueError, match="label"):
        mapper.integrate(points, pose_at())
    assert mapper.counts()["known"] == 0


def test_pose_must_be_a_rigid_4_by_4(mapper):
    points, labels = wall()
    with pytest.raises(ValueError, match=r"^pose: expected a \(4, 4\) matrix, got shape \(3, 4\)"):
        mapper.integrate(points, pose_at()[:3], labels=labels)
    scaled = pose_at()
    scaled[:3, :3] *= 2
    with pytest.raises(ValueError, match=r"^pose"):
        mapper.integrate(points, scaled, labels=labels)
    nan = pose_at()
    nan[0, 3] = np.nan
    with pytest.raises(ValueError, match=r"^pose.*NaN"):
        mapper.integrate(points, nan, labels=labels)
    last_row = pose_at()
    last_row[3, 0] = 1
    with pytest.raises(ValueError, match=r"^pose"):
        mapper.integrate(points, last_row, labels=labels)
    with pytest.raises(TypeError, match=r"^pose: "):
        mapper.integrate(points, "identity", labels=labels)
    assert mapper.counts()["known"] == 0


def test_frame_and_origin(mapper):
    points, labels = wall()
    with pytest.raises(ValueError, match=r'^frame: expected "sensor" or "world", got "map"'):
        mapper.integrate(points, pose_at(), labels=labels, frame="map")
    with pytest.raises(TypeError, match=r"^frame: "):
        mapper.integrate(points, pose_at(), labels=labels, frame=1)
    with pytest.raises(ValueError, match=r"^origin: coordinates must be finite"):
        mapper.integrate(points, pose_at(), labels=labels, frame="world", origin=[0, np.inf, 0])
    with pytest.raises(ValueError, match=r"^origin: expected 3 coordinates"):
        mapper.integrate(points, pose_at(), labels=labels, frame="world", origin=[0, 0])


def test_a_scan_beyond_the_map_limits_is_refused_and_changes_nothing(mapper):
    points, labels = wall()
    mapper.integrate(points, pose_at(), labels=labels)
    counts = mapper.counts()
    with pytest.raises(ValueError, match=r"scan 1 .*beyond the map limits"):
        mapper.integrate(points, pose_at(x=2e4), labels=labels)
    assert mapper.counts() == counts and mapper.scans == 1
    # Listed in the profile as `sarmap run` lists a skipped scan.
    skipped = mapper.profile()["skipped"]
    assert len(skipped) == 1 and skipped[0]["scan"] == 1 and "beyond the map limits" in skipped[0]["error"]


def test_non_finite_points_are_dropped_and_counted(mapper):
    points, labels = wall()
    points[::10, 1] = np.nan
    points[5, 2] = np.inf
    mapper.integrate(points, pose_at(), labels=labels)
    assert mapper.dropped_non_finite == 41
    assert mapper.profile()["stages"]["preprocess"]["points_in"] == 400 - 41


def test_sensor_and_world_frames(mapper):
    """frame="sensor" moves points by the pose; frame="world" takes them as they are."""
    points, labels = wall()
    pose = pose_at(x=1.0, y=2.0, yaw=math.pi / 2)
    mapper.integrate(points, pose, labels=labels)
    world = sarmap.Mapper(LABELS)
    moved = (points.astype(np.float64) @ pose[:3, :3].T + pose[:3, 3]).astype(np.float32)
    world.integrate(moved, pose, labels=labels, frame="world")
    a, _ = mapper.occupied_voxels()
    b, _ = world.occupied_voxels()
    assert len(a) > 50
    np.testing.assert_array_equal(a, b)
    # The wall stands at y = 4 once turned by 90 degrees about z and moved.
    assert np.all(np.abs(a[:, 1] - 4.0) < 0.1)
    # Near the sensor every ray of the fan crosses the same few voxels: seen free.
    assert mapper.state_at([1.0, 2.3, 0.5]) == sarmap.FREE


def test_config_keys_and_types_are_checked():
    with pytest.raises(ValueError, match=r"config: classifier\.colour: unknown key"):
        sarmap.Mapper({"classifier": {"kind": "labels", "colour": 1}})
    with pytest.raises(ValueError, match=r"config: voxel"):
        sarmap.Mapper({"voxel": "fine", "classifier": {"kind": "labels"}})
    with pytest.raises(ValueError, match="classifier"):
        sarmap.Mapper({"classifier": {"kind": "neural"}})
    with pytest.raises(TypeError, match=r"^config: expected a dict"):
        sarmap.Mapper(42)
    with pytest.raises(TypeError, match=r"^config: .*not JSON serializable"):
        sarmap.Mapper({"voxel": object()})
    with pytest.raises(OSError, match="no_such_config.json"):
        sarmap.Mapper("no_such_config.json")
    with pytest.raises(ValueError, match=r"^sensor: kind: unknown key"):
        sarmap.Mapper(LABELS, sensor={"kind": "lidar"})
    with pytest.raises(ValueError, match=r'^sensor: type: expected "depth_camera"'):
        sarmap.Mapper(LABELS, sensor={"type": "radar"})
    mapper = sarmap.Mapper({"voxel": 0.1, "classifier": {"kind": "labels"}}, sensor={"type": "lidar", "max_range": 8})
    assert mapper.resolution == 0.1
    assert mapper.config["voxel"] == 0.1 and mapper.config["classifier"]["kind"] == "labels"


def test_queries_check_their_points(mapper):
    with pytest.raises(TypeError, match=r"^points: expected a float32 or float64 array.*int64"):
        mapper.state_at(np.zeros((4, 3), dtype=np.int64))
    with pytest.raises(ValueError, match=r"^points: expected points of shape \(\.\.\., 3\), got \(4, 2\)"):
        mapper.class_at(np.zeros((4, 2)))
    with pytest.raises(TypeError, match=r"^points: "):
        mapper.probability_at("here")
    assert mapper.state_at([0.0, 0.0, 0.0]).shape == ()
    assert mapper.state_at(np.zeros((0, 3))).shape == (0,)


def test_plan_checks_its_arguments(mapper):
    with pytest.raises(ValueError, match=r'^graph: expected "tree", "roadmap" or "grid", got "maze"'):
        mapper.plan([0, 0, 0], [1, 0, 0], graph="maze")
    with pytest.raises(ValueError, match=r'^algorithm: expected "dijkstra" or "astar"'):
        mapper.plan([0, 0, 0], [1, 0, 0], algorithm="bfs")
    with pytest.raises(ValueError, match=r"^goal: coordinates must be finite"):
        mapper.plan([0, 0, 0], [np.nan, 0, 0])
    route = mapper.plan([0, 0, 0], [1, 0, 0])
    assert route["found"] is False and route["reason"]


def test_classify_checks_its_arguments():
    points, _ = wall()
    with pytest.raises(ValueError, match=r'^config: classifier\.kind "labels"'):
        sarmap.classify(points, LABELS)
    points[3, 0] = np.nan
    with pytest.raises(ValueError, match=r"^points: point 3 is not finite"):
        sarmap.classify(points, {"classifier": {"kind": "geometric"}})


def test_files_that_cannot_be_read_are_os_errors(tmp_path):
    with pytest.raises(OSError, match="missing.ply"):
        sarmap.read_cloud(tmp_path / "missing.ply")
    with pytest.raises(OSError):
        sarmap.open_sequence(tmp_path / "no_sequence")
    (tmp_path / "bad.ply").write_text("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n")
    with pytest.raises(ValueError, match="bad.ply"):
        sarmap.read_cloud(tmp_path / "bad.ply")
    with pytest.raises(ValueError, match="unknown"):
        sarmap.write_cloud(tmp_path / "cloud.xyz", np.zeros((1, 3), np.float32))
    with pytest.raises(TypeError, match="^path: "):
        sarmap.read_cloud(3)


def test_the_shipped_model_is_found_as_the_binary_finds_it(monkeypatch, tmp_path):
    assert sarmap.Mapper().config["classifier"]["model"] == sarmap.shipped_model()
    # SARMAP_DATA_DIR, when set, is the only place looked.
    monkeypatch.setenv("SARMAP_DATA_DIR", str(tmp_path))
    with pytest.raises(FileNotFoundError, match=f"{tmp_path}/models/ramps-dgcnn.safetensors, from SARMAP_DATA_DIR"):
        sarmap.Mapper()
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "ramps-dgcnn.safetensors").write_bytes(b"not a model")
    assert sarmap.shipped_model() == str(tmp_path / "models" / "ramps-dgcnn.safetensors")
    with pytest.raises(ValueError, match="ramps-dgcnn.safetensors"):
        sarmap.Mapper()
