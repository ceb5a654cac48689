"""tools/python/training_blocks.py's map-level blocks: the accumulated map
keeps the first point of each cube as a plain loop does, the map's cuts keep
only cells that grew, a LiDAR arena gives map-level blocks end to end, and
--vary-mount draws each arena's mounting from its seed within the ranges."""

import os
import shlex
import sys

import numpy as np

from conftest import cli_path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "python"))
import training_blocks  # noqa: E402


def random_frames(seed, count=5, n=400):
    rng = np.random.default_rng(seed)
    frames = []
    for _ in range(count):
        xyz = rng.uniform(-1.0, 3.0, (n, 3))
        xyz[: n // 4] = np.round(xyz[: n // 4] / 0.05) * 0.05  # points on cube faces and shared cubes
        frames.append((xyz, rng.integers(0, 6, n).astype(np.uint8)))
    return frames


def test_the_map_keeps_the_first_point_of_each_cube_as_a_plain_loop():
    for seed in range(3):
        frames = random_frames(seed)
        xyz, labels, birth = training_blocks.map_points(frames, 0.1)
        expected = {}
        for f, (fx, fl) in enumerate(frames):
            for p in range(len(fx)):
                key = tuple(np.floor(fx[p] / 0.1).astype(np.int64))
                if key not in expected:
                    expected[key] = (tuple(fx[p]), fl[p], f)
        got = {tuple(np.floor(xyz[k] / 0.1).astype(np.int64)): (tuple(xyz[k]), labels[k], birth[k])
               for k in range(len(xyz))}
        assert len(xyz) == len(expected)
        assert got == expected
        assert list(birth) == sorted(birth)  # in the order the frames added them
    empty = training_blocks.map_points([], 0.1)
    assert len(empty[0]) == 0


def test_the_map_is_cut_into_grown_cells_only():
    frames = random_frames(7, count=8, n=300)
    blocks = list(training_blocks.map_snapshot_cells(frames, 0.05, 4, 1.0, 20))
    assert blocks
    sizes = {}
    for origin, xyz, labels in blocks:
        assert len(xyz) >= 20 and len(xyz) == len(labels)
        assert np.all(xyz[:, 0] >= origin[0]) and np.all(xyz[:, 0] < origin[0] + 1.0)
        assert np.all(xyz[:, 1] >= origin[1]) and np.all(xyz[:, 1] < origin[1] + 1.0)
        assert len(xyz) > sizes.get(origin, 0)  # a cell is cut again only once it has grown
        sizes[origin] = len(xyz)
    # The last cut holds every cell of the whole map.
    all_xyz, _, _ = training_blocks.map_points(frames, 0.05)
    whole = {origin: len(idx) for origin, idx in training_blocks.cells(all_xyz, 1.0, 20)}
    assert sizes == whole


def test_a_lidar_arena_gives_map_level_blocks(tmp_path):
    out = tmp_path / "lidar.npz"
    training_blocks.main(["--sarmap", cli_path(), "--seeds", "1000", "--sensor", "lidar",
                          "--sensor-args", "--rings 8 --samples 720", "--frames", "6", "--map-cell", "0.025",
                          "--snapshots", "2", "--block-size", "1.5", "--min-points", "100", "--out", str(out)])
    data = np.load(out)
    assert str(data["sensor"]) == "lidar" and str(data["sensor_args"]) == "--rings 8 --samples 720"
    assert set(data["block_mount"].astype(str)) == {"--rings 8 --samples 720"}
    assert float(data["map_cell"]) == 0.025 and int(data["snapshots"]) == 2
    blocks = len(data["arena"])
    assert blocks > 0 and len(data["offsets"]) == blocks + 1
    sizes = np.diff(data["offsets"])
    assert np.all(sizes >= 100) and np.all(sizes <= 2048)
    assert set(np.unique(data["labels"])) <= set(range(6)) and len(set(np.unique(data["labels"])) - {0}) >= 2


def test_joined_files_hold_every_block_of_each_with_its_sensor(tmp_path):
    import join_blocks
    rng = np.random.default_rng(3)

    def blocks_file(path, sensor, sizes, seed):
        offsets = np.r_[0, np.cumsum(sizes)].astype(np.int64)
        np.savez(path, points=rng.normal(size=(offsets[-1], 3)).astype(np.float32),
                 labels=rng.integers(0, 6, offsets[-1]).astype(np.uint8), offsets=offsets,
                 origins=rng.normal(size=(len(sizes), 2)), arena=np.full(len(sizes), seed, np.int64),
                 block_size=np.float64(1.5), min_points=np.int64(100), sensor=np.str_(sensor),
                 map_cell=np.float64(0.025), snapshots=np.int64(4))
        return np.load(path)

    a = blocks_file(tmp_path / "a.npz", "depth", [120, 300], 1000)
    b = blocks_file(tmp_path / "b.npz", "lidar", [150, 101, 200], 1001)
    joined = join_blocks.join([tmp_path / "a.npz", tmp_path / "b.npz"])
    assert list(joined["block_sensor"]) == ["depth"] * 2 + ["lidar"] * 3
    assert list(joined["arena"]) == [1000] * 2 + [1001] * 3
    assert float(joined["map_cell"]) == 0.025 and int(joined["snapshots"]) == 4
    for k, (src, block) in enumerate([(a, 0), (a, 1), (b, 0), (b, 1), (b, 2)]):
        lo, hi = joined["offsets"][k], joined["offsets"][k + 1]
        slo, shi = src["offsets"][block], src["offsets"][block + 1]
        assert np.array_equal(joined["points"][lo:hi], src["points"][slo:shi])
        assert np.array_equal(joined["labels"][lo:hi], src["labels"][slo:shi])
    np.savez(tmp_path / "c.npz", **{**dict(b), "block_size": np.float64(1.0)})
    try:
        join_blocks.join([tmp_path / "a.npz", tmp_path / "c.npz"])
        assert False, "files of different block sizes were joined"
    except SystemExit as error:
        assert "block sizes differ" in str(error)


def test_mountings_are_drawn_from_the_seed_within_their_ranges():
    seen = {"depth": set(), "lidar": set()}
    for sensor in ("depth", "lidar"):
        for seed in range(1000, 1060):
            args = training_blocks.mount_args(sensor, seed)
            assert args == training_blocks.mount_args(sensor, seed)  # the seed alone decides
            options = dict(zip(args[::2], args[1::2]))
            height = float(options["--sensor-height"])
            if sensor == "lidar":
                assert (int(options["--rings"]), options["--vertical-fov"]) in training_blocks.LIDAR_RINGS
                assert int(options["--max-range"]) in training_blocks.LIDAR_RANGES
                assert 0.3 <= height <= 1.2
            else:
                assert (int(options["--width"]), int(options["--height"])) in training_blocks.CAMERA_SIZES
                assert 0.3 <= height <= 1.0 and -30.0 <= float(options["--pitch"]) <= -5.0
            seen[sensor].add(tuple(args))
    # Sixty arenas give many mountings, every ring count and camera size among them.
    assert len(seen["lidar"]) > 50 and len(seen["depth"]) > 50
    assert {a[1] for a in seen["lidar"]} == {str(r) for r, _ in training_blocks.LIDAR_RINGS}
    assert {a[1] for a in seen["depth"]} == {str(w) for w, _ in training_blocks.CAMERA_SIZES}


def test_varied_mountings_simulate_and_are_recorded_per_block(tmp_path):
    # Seeds whose draws differ; a few frames each, the camera's and the LiDAR's.
    for sensor, extra in (("lidar", ["--sensor-args", "--samples 360"]), ("depth", [])):
        out = tmp_path / f"{sensor}.npz"
        training_blocks.main(["--sarmap", cli_path(), "--seeds", "1000-1001", "--sensor", sensor, *extra,
                              "--vary-mount", "--frames", "4", "--map-cell", "0.025", "--snapshots", "1",
                              "--block-size", "1.5", "--min-points", "50", "--out", str(out)])
        data = np.load(out)
        mounts = data["block_mount"].astype(str)
        assert len(mounts) == len(data["arena"]) > 0
        after = shlex.split(extra[1]) if extra else []  # --sensor-args come after the mounting
        for seed in (1000, 1001):
            expected = shlex.join(training_blocks.mount_args(sensor, seed) + after)
            assert set(mounts[data["arena"] == seed]) <= {expected}
        assert len(set(mounts)) == len(set(data["arena"].tolist()))
