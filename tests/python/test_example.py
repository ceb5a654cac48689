"""examples/python/map_sequence.py, run as a user would, writes the run the
sarmap binary writes."""

import os
import subprocess
import sys

from conftest import FRAMES

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python", "map_sequence.py")


def test_map_sequence_example(sequence_dir, labels_config, cli_run, tmp_path):
    out = tmp_path / "run"
    result = subprocess.run([sys.executable, EXAMPLE, str(sequence_dir), str(out), str(labels_config)],
                            capture_output=True, text=True, env=os.environ)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"{FRAMES} scans: ")
    assert (out / "map.sarmap").read_bytes() == (cli_run / "map.sarmap").read_bytes()
    assert (out / "manifest.json").is_file()
