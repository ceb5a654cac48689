"""Native calls release the GIL, so other Python threads run meanwhile, and a
Mapper takes one call at a time when threads share it."""

import threading
import time

import numpy as np

import sarmap

LABELS = {"classifier": {"kind": "labels"}}


def hemisphere(n, seed):
    """n points on a 3 m half sphere around the sensor, labelled wall."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d[:, 0] = np.abs(d[:, 0])
    points = (3.0 * d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)
    return points, np.full(n, 2, np.uint8)


def test_integrate_lets_other_threads_run():
    points, labels = hemisphere(400_000, 1)
    mapper = sarmap.Mapper(LABELS)
    call = {}

    def work():
        call["start"] = time.perf_counter()
        mapper.integrate(points, np.eye(4), labels=labels)
        call["end"] = time.perf_counter()

    thread = threading.Thread(target=work)
    ticks = []
    thread.start()
    while thread.is_alive():
        ticks.append(time.perf_counter())
    thread.join()
    inside = [t for t in ticks if call["start"] <= t <= call["end"]]
    duration = call["end"] - call["start"]
    # Holding the GIL, the call would leave this thread no tick inside it but
    # at its two ends; released, the ticks run on all along it.
    assert duration > 0.05, "the scan is too small to tell"
    gaps = np.diff([call["start"], *inside, call["end"]])
    assert gaps.max() < duration / 2, f"longest pause {gaps.max():.3f} s of a {duration:.3f} s call"


def test_threads_sharing_a_mapper_take_turns():
    mapper = sarmap.Mapper(LABELS)
    scans = [hemisphere(20_000, seed) for seed in range(8)]
    errors = []

    def work(part):
        try:
            for points, labels in part:
                mapper.integrate(points, np.eye(4), labels=labels)
                mapper.state_at(points[:100])
        except Exception as e:  # reported below: a thread's exception is not the test's
            errors.append(e)

    threads = [threading.Thread(target=work, args=(scans[i::2],)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    assert mapper.scans == 8
    alone = sarmap.Mapper(LABELS)
    for points, labels in scans:
        alone.integrate(points, np.eye(4), labels=labels)
    # Every scan hit the same walls: the same occupied voxels in any order.
    assert mapper.counts()["occupied"] == alone.counts()["occupied"]
