"""Fixtures of the Python module's tests: the built sarmap binary, a small
simulated sequence, and the binary's own run on it, which the module's results
are held to. ctest sets SARMAP_CLI; run by hand, the binary is taken from the
build tree that holds the imported package (docs/python.md, "Tests")."""

import json
import os
import subprocess

import pytest

import sarmap

# A few frames of the default arena, labelled by the simulator: the labels
# classifier keeps these tests to the mapping itself, in a few seconds.
FRAMES = 6
LABELS_CONFIG = {"classifier": {"kind": "labels"}}


def cli_path():
    if os.environ.get("SARMAP_CLI"):
        return os.environ["SARMAP_CLI"]
    build = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(sarmap.__file__))))
    return os.path.join(build, "tools", "sarmap", "sarmap")


def run_cli(*args):
    """Runs the sarmap binary; fails the test with its stderr unless it succeeds."""
    result = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True)
    assert result.returncode == 0, f"sarmap {' '.join(map(str, args))} failed: {result.stderr}"
    return result


@pytest.fixture(scope="session")
def sequence_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("sequence") / "esogu"
    run_cli("simulate", sarmap.shipped_arena(), "--out", out, "--frames", FRAMES, "--quiet")
    return out


@pytest.fixture(scope="session")
def labels_config(tmp_path_factory):
    path = tmp_path_factory.mktemp("config") / "labels.json"
    path.write_text(json.dumps(LABELS_CONFIG))
    return path


@pytest.fixture(scope="session")
def cli_run(sequence_dir, labels_config, tmp_path_factory):
    """`sarmap run` on the sequence with the labels classifier."""
    out = tmp_path_factory.mktemp("cli") / "run"
    run_cli("run", sequence_dir, "--config", labels_config, "--out", out, "--quiet")
    return out


@pytest.fixture(scope="session")
def module_mapper(sequence_dir, labels_config):
    """The module's Mapper on the same sequence and config, frames from open_sequence."""
    sequence = sarmap.open_sequence(sequence_dir)
    mapper = sarmap.Mapper(labels_config, sensor=sequence.sensor)
    for points, pose, origin in sequence:
        mapper.integrate(points, pose, frame="world", origin=origin)
    mapper.finish()
    return mapper
