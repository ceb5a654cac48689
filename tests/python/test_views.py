"""Arrays cross without copies where the engine's layout allows, and a view
keeps the memory it shows alive after everything else that held it is gone."""

import gc
import weakref

import numpy as np

import sarmap


def make_cloud(n=1000):
    rng = np.random.default_rng(3)
    points = rng.uniform(-2, 2, (n, 3)).astype(np.float32)
    labels = rng.integers(0, 6, n).astype(np.uint8)
    return points, labels, sarmap.PointCloud(points, labels=labels,
                                             scores={"confidence": rng.uniform(0, 1, n).astype(np.float32)})


def test_cloud_arrays_are_views_of_one_buffer():
    points, labels, cloud = make_cloud()
    x = cloud.x
    assert x.dtype == np.float32 and x.shape == (1000,)
    # Two reads give the same memory, and a write through one shows in the other and in the copies.
    assert cloud.x.ctypes.data == x.ctypes.data
    assert cloud.labels.ctypes.data == cloud.labels.ctypes.data
    x[0] = 42.0
    assert cloud.x[0] == 42.0 and cloud.xyz[0, 0] == 42.0 and np.asarray(cloud)[0, 0] == 42.0
    cloud.scores["confidence"][1] = 7.0
    assert cloud.scores["confidence"][1] == 7.0
    # The constructor copied its inputs: the caller's arrays are untouched.
    assert points[0, 0] != 42.0
    np.testing.assert_array_equal(cloud.labels, labels)
    np.testing.assert_array_equal(cloud.y, points[:, 1])
    # xyz is one (N, 3) array gathered from three: a copy.
    assert not np.shares_memory(cloud.xyz, cloud.x)


def test_a_view_keeps_its_cloud_alive():
    points, labels, cloud = make_cloud()
    z, lab = cloud.z, cloud.labels
    alive = weakref.ref(cloud)
    del cloud
    gc.collect()
    assert alive() is not None  # held by the views' base
    np.testing.assert_array_equal(z, points[:, 2])
    np.testing.assert_array_equal(lab, labels)
    del z
    gc.collect()
    assert alive() is not None
    del lab
    gc.collect()
    assert alive() is None


def test_read_cloud_arrays_outlive_the_call(tmp_path):
    points, labels, cloud = make_cloud()
    sarmap.write_cloud(tmp_path / "c.ply", cloud)
    x = sarmap.read_cloud(tmp_path / "c.ply").x  # the cloud object is gone at once
    gc.collect()
    np.testing.assert_array_equal(x, points[:, 0])


def test_classify_labels_outlive_everything(tmp_path):
    points, _, _ = make_cloud(3000)
    labels, scores = sarmap.classify(points, {"classifier": {"kind": "geometric"}})
    gc.collect()
    assert labels.dtype == np.uint8 and labels.shape == (3000,)
    assert labels.base is not None  # the engine's own buffer, not a copy
    assert labels.max() < len(sarmap.CLASS_NAMES)


def test_occupied_voxel_classes_outlive_the_mapper():
    rng = np.random.default_rng(5)
    n = 2000
    points = np.column_stack([np.full(n, 2.0), rng.uniform(-1, 1, n), rng.uniform(-0.5, 0.5, n)]).astype(np.float32)
    mapper = sarmap.Mapper({"classifier": {"kind": "labels"}})
    mapper.integrate(points, np.eye(4), labels=np.full(n, 2, np.uint8))
    centres, classes = mapper.occupied_voxels()
    cloud = mapper.voxel_cloud()
    del mapper
    gc.collect()
    assert len(classes) == len(centres) == len(cloud) > 100
    assert (classes == 2).all()
    np.testing.assert_array_equal(cloud.labels, classes)
    assert (cloud.scores["probability"] > 0.5).all()
