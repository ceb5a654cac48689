"""classify() against `sarmap classify` on the same cloud: the same classifier
and rules, so the same labels and scores."""

import numpy as np

import sarmap
from conftest import run_cli


def test_classify_matches_sarmap_classify(sequence_dir, tmp_path):
    # A quarter of one frame's points keeps the network's run short.
    frame = sarmap.read_cloud(sequence_dir / "frame_000003.ply")
    points = np.ascontiguousarray(frame.xyz[::4])
    cloud = tmp_path / "cloud.ply"
    sarmap.write_cloud(cloud, points)
    out = tmp_path / "classified.ply"
    run_cli("classify", cloud, "--out", out, "--quiet")
    expected = sarmap.read_cloud(out)

    labels, scores = sarmap.classify(points)  # the shipped DGCNN by default
    np.testing.assert_array_equal(labels, expected.labels)
    assert scores.shape == (len(points), len(sarmap.CLASS_NAMES)) and scores.dtype == np.float32
    named = [k for k, name in enumerate(sarmap.CLASS_NAMES) if name in expected.scores]
    assert len(named) >= 4
    for k in named:
        np.testing.assert_array_equal(scores[:, k], expected.scores[sarmap.CLASS_NAMES[k]])
    # The network found more than one class on a view of the arena.
    assert len(np.unique(labels)) >= 2
    # Where it gives scores, the label is the best-scored class.
    scored = scores.sum(axis=1) > 0
    np.testing.assert_array_equal(labels[scored], scores[scored].argmax(axis=1))


def test_geometric_classifier_has_no_scores(sequence_dir):
    frame = sarmap.read_cloud(sequence_dir / "frame_000003.ply")
    labels, scores = sarmap.classify(frame, {"classifier": {"kind": "geometric"}})
    assert labels.shape == (len(frame),)
    assert scores is None
    # The frame's own labels (the simulator's ground truth) are left alone.
    assert frame.labels is not None and not np.shares_memory(labels, frame.labels)
