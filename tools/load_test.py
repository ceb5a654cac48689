#!/usr/bin/env python3
# The load test of issue 33 ("Reliability", docs/reliability.md, "Long runs:
# memory over time"): runs `sarmap run SEQ --out OUT --classifier labels
# --quiet --no-overlap [--max-blocks N]`, samples the process's resident memory (VmRSS and
# VmHWM from /proc/PID/status) every --interval seconds, maps each sample's time
# to the scans done from OUT/profile.json's per-scan times, writes a CSV and
# prints peak RSS, RSS at 10/25/50/75/100 % of the scans and the slope over the
# second half in MB per 1,000 scans. `--check-flat MB` exits 1 when that slope
# exceeds MB (the CI variant, tests/cli/CMakeLists.txt, runs it with
# --max-blocks). Python 3 standard library only; Linux (/proc).
#
#   tools/load_test.py --sequence /tmp/seq --out /tmp/run --max-blocks 1000
#   tools/load_test.py --arena datasets/arenas/building-52x15.json --frames 300 \
#       --image-scale 0.25 --sequence /tmp/seq --out /tmp/run --max-blocks 300 --check-flat 400
#   tools/load_test.py --sequence /tmp/seq --out /tmp/run -- --threads 1   (more `sarmap run` options)
#
# With --arena, the arena is simulated into --sequence first (`sarmap simulate`),
# from a copy whose trajectory has --frames frames and whose depth camera is
# scaled by --image-scale. Exit codes: 0 done (and flat), 1 --check-flat
# failed, 2 a usage error or a failed sarmap, 130 interrupted.
import argparse
import csv
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SARMAP = os.path.join(REPO, "build", "release", "tools", "sarmap", "sarmap")
QUANTILES = (10, 25, 50, 75, 100)


class Failure(Exception):
    """A usage error or a failed step: printed as `load_test: ...`, exit 2."""


class Interrupted(Exception):
    pass


def on_signal(signum, _frame):
    raise Interrupted(signal.Signals(signum).name)


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Memory over time of a long `sarmap run` (issue 33, docs/reliability.md).",
        epilog="Arguments after `--` go to `sarmap run` as they are.")
    p.add_argument("--sarmap", default=DEFAULT_SARMAP, help="the sarmap binary (default: %(default)s)")
    p.add_argument("--sequence", required=True, help="the sequence folder to run (with --arena: simulated into it)")
    p.add_argument("--out", required=True, help="the run's output folder (sarmap run --out)")
    p.add_argument("--max-blocks", type=int,
                   help="sarmap run --max-blocks (0: no limit; left out: sarmap's default)")
    p.add_argument("--classifier", default="labels", help="sarmap run --classifier (default: %(default)s)")
    p.add_argument("--csv", help="where the samples go (default: OUT/memory.csv)")
    p.add_argument("--interval", type=float, default=0.5, help="seconds between samples (default: %(default)s)")
    p.add_argument("--check-flat", type=float, metavar="MB_PER_1000_SCANS",
                   help="exit 1 when the second half's RSS slope exceeds this")
    p.add_argument("--arena", help="simulate this arena into --sequence first")
    p.add_argument("--frames", type=int, help="with --arena: the trajectory's frame count")
    p.add_argument("--image-scale", type=float, help="with --arena: scale the depth camera's image by this")
    p.add_argument("--seed", type=int, default=0, help="with --arena: the noise seed (default: %(default)s)")
    p.add_argument("sarmap_args", nargs="*", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.max_blocks is not None and a.max_blocks < 0:
        p.error("--max-blocks must be >= 0")
    if not (a.interval > 0):
        p.error("--interval must be > 0")
    if a.check_flat is not None and not (a.check_flat >= 0):
        p.error("--check-flat must be a number >= 0")
    if a.arena is None and (a.frames is not None or a.image_scale is not None):
        p.error("--frames and --image-scale need --arena")
    if a.frames is not None and a.frames < 2:
        p.error("--frames must be at least 2")
    if a.image_scale is not None and not (0 < a.image_scale <= 4):
        p.error("--image-scale must be in (0, 4]")
    if os.path.abspath(a.out) == os.path.abspath(a.sequence):
        p.error("--out must differ from --sequence")
    return a


def check_binary(path):
    if not os.path.isfile(path):
        raise Failure(f"{path}: no such file (build it: cmake --build --preset release --target sarmap_cli, "
                      f"or give --sarmap BIN)")
    if not os.access(path, os.X_OK):
        raise Failure(f"{path}: not executable")


def simulate(a):
    """Writes a copy of the arena with the asked trajectory and image, then simulates it into a.sequence."""
    try:
        with open(a.arena) as f:
            arena = json.load(f)
    except (OSError, ValueError) as e:
        raise Failure(f"{a.arena}: {e}")
    if not isinstance(arena, dict):
        raise Failure(f"{a.arena}: not a JSON object")
    if a.frames is not None:
        trajectory = arena.get("trajectory")
        if not isinstance(trajectory, dict) or "waypoints" not in trajectory:
            raise Failure(f"{a.arena}: --frames needs a trajectory with waypoints")
        trajectory["frames"] = a.frames
    if a.image_scale is not None:
        sensor = arena.get("sensor")
        if not isinstance(sensor, dict) or sensor.get("type") != "depth_camera":
            raise Failure(f"{a.arena}: --image-scale needs a depth_camera sensor")
        for key in ("width", "height"):
            sensor[key] = max(1, round(sensor[key] * a.image_scale))
        for key in ("fx", "fy", "cx", "cy"):
            sensor[key] = sensor[key] * a.image_scale
    # Mesh paths are relative to the arena file: make them absolute for the copy.
    base = os.path.dirname(os.path.abspath(a.arena))
    for element in arena.get("elements", []):
        if isinstance(element, dict) and element.get("type") == "mesh" and isinstance(element.get("path"), str):
            element["path"] = os.path.join(base, element["path"])
    with tempfile.TemporaryDirectory(prefix="sarmap-load-") as tmp:
        copy = os.path.join(tmp, "arena.json")
        with open(copy, "w") as f:
            json.dump(arena, f)
        cmd = [a.sarmap, "simulate", copy, "--out", a.sequence, "--seed", str(a.seed), "--quiet"]
        started = time.monotonic()
        result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if result.returncode != 0:
            raise Failure(f"simulate failed ({result.returncode}): {' '.join(cmd)}\n{result.stderr.strip()}")
    print(f"simulated {a.arena} into {a.sequence} in {time.monotonic() - started:.1f} s", flush=True)


def process_name(pid):
    try:
        with open(f"/proc/{pid}/comm") as f:
            return f.read().strip()
    except OSError:
        return None


def read_status(pid, parent_name):
    """VmRSS and VmHWM in MB, or None before the child's exec and once it is gone (or a zombie)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            fields = dict(line.split(":", 1) for line in f if ":" in line)
    except (FileNotFoundError, ProcessLookupError):
        return None
    if fields.get("Name", "").strip() == parent_name:  # not yet exec'd: still a copy of this Python
        return None
    try:
        rss = int(fields["VmRSS"].split()[0]) / 1024.0
        hwm = int(fields["VmHWM"].split()[0]) / 1024.0
    except (KeyError, ValueError, IndexError):
        return None
    return rss, hwm


def stop(proc):
    """Ends the child: SIGTERM, then SIGKILL after 5 s."""
    if proc.returncode is not None:
        return
    try:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    except ProcessLookupError:
        pass


def run_and_sample(a):
    """Runs sarmap, returning (samples [(t, rss, hwm)], exit code, peak RSS in MB from rusage, seconds)."""
    # In order: the per-scan stage times then add up to the run's time line
    # (overlapped, two scans' stages would count twice).
    cmd = [a.sarmap, "run", a.sequence, "--out", a.out, "--classifier", a.classifier, "--quiet", "--no-overlap"]
    if a.max_blocks is not None:
        cmd += ["--max-blocks", str(a.max_blocks)]
    cmd += a.sarmap_args
    print("running: " + " ".join(cmd), flush=True)
    samples = []
    parent_name = process_name("self")
    stderr = tempfile.TemporaryFile(mode="w+")
    started = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=stderr)
    try:
        next_sample = started
        while True:
            # Reaped here (not by Popen) to get the child's own peak RSS from rusage.
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                proc.returncode = os.waitstatus_to_exitcode(status)
                ended = time.monotonic()
                break
            now = time.monotonic()
            if now >= next_sample:
                s = read_status(proc.pid, parent_name)
                if s is not None:
                    samples.append((now - started, s[0], s[1]))
                next_sample += a.interval
                if next_sample < now:  # fell behind (a loaded machine): sample from now on
                    next_sample = now + a.interval
            time.sleep(min(0.02, max(0.0, next_sample - time.monotonic())))
    except BaseException:
        stop(proc)
        raise
    stderr.seek(0)
    err = stderr.read().strip()
    if proc.returncode != 0:
        raise Failure(f"sarmap run failed ({proc.returncode}): {' '.join(cmd)}\n{err}")
    if err:
        print(err, file=sys.stderr)
    return samples, usage.ru_maxrss / 1024.0, ended - started


def scan_end_times(out):
    """Seconds from the run's start to each scan's end: the cumulative per-scan times of profile.json.

    The CLI opens the sequence and builds the Mapper before the first scan (a
    few ms), and the per-scan rows time everything in the loop (read and every
    stage), so the sum is the loop's time to within the untimed bookkeeping.
    """
    path = os.path.join(out, "profile.json")
    try:
        with open(path) as f:
            profile = json.load(f)
        rows = profile["per_scan"]
        ends, t = [], 0.0
        for row in rows:
            t += sum(v for k, v in row.items() if k.endswith("_s") and k != "latency_s")
            ends.append(t)
        return ends, profile
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
        raise Failure(f"{path}: cannot read the per-scan times: {e}")


def scans_done_at(t, ends):
    """How many scans had ended by time t (binary search over the sorted end times)."""
    lo, hi = 0, len(ends)
    while lo < hi:
        mid = (lo + hi) // 2
        if ends[mid] <= t:
            lo = mid + 1
        else:
            hi = mid
    return lo


def slope_per_1000(points):
    """Least-squares slope of (scans, MB) points, in MB per 1,000 scans; None with fewer than 2 distinct x."""
    n = len(points)
    if n < 2:
        return None
    mx = sum(x for x, _ in points) / n
    my = sum(y for _, y in points) / n
    sxx = sum((x - mx) ** 2 for x, _ in points)
    if sxx == 0:
        return None
    sxy = sum((x - mx) * (y - my) for x, y in points)
    return 1000.0 * sxy / sxx


def blocks_setting(max_blocks):
    if max_blocks is None:
        return "sarmap's default"
    return "0 (no limit)" if max_blocks == 0 else str(max_blocks)


def main(argv):
    a = parse_args(argv)
    check_binary(a.sarmap)
    if a.arena:
        simulate(a)
    if not os.path.isfile(os.path.join(a.sequence, "sequence.json")):
        raise Failure(f"{a.sequence}: no sequence.json (give a sarmap sequence folder, or --arena to simulate one)")
    samples, peak_rss, seconds = run_and_sample(a)
    ends, profile = scan_end_times(a.out)
    scans = len(ends)
    if scans == 0:
        raise Failure(f"{a.out}/profile.json: no scans")
    loop_end = ends[-1]
    rows = [(t, scans_done_at(t, ends), "map" if t <= loop_end else "write", rss, hwm) for t, rss, hwm in samples]

    csv_path = a.csv or os.path.join(a.out, "memory.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time_s", "scans_done", "phase", "rss_mb", "hwm_mb"])
        for t, done, phase, rss, hwm in rows:
            w.writerow([f"{t:.3f}", done, phase, f"{rss:.1f}", f"{hwm:.1f}"])

    mapping = [r for r in rows if r[2] == "map"]
    print(f"scans: {scans} in {seconds:.1f} s ({profile.get('scans_per_second', 0):.1f} scans/s by profile.json; "
          f"mapping {loop_end:.1f} s, then writing); {len(samples)} samples, {len(mapping)} while mapping; "
          f"max-blocks: {blocks_setting(a.max_blocks)}")
    print(f"peak RSS: {peak_rss:.1f} MB (whole run, writing included); "
          f"{max((r[3] for r in mapping), default=float('nan')):.1f} MB sampled while mapping")
    if len(mapping) < 8:
        raise Failure(f"only {len(mapping)} samples while mapping: too short a run to judge "
                      f"(more frames, or a smaller --interval)")
    at = []
    for q in QUANTILES:
        target = scans * q / 100.0
        # The sample nearest to q % of the scans (100 %: the last one while mapping).
        r = mapping[-1] if q == 100 else min(mapping, key=lambda r: abs(r[1] - target))
        at.append((q, r))
        print(f"  RSS at {q:3d} % ({r[1]:5d} scans, {r[0]:7.1f} s): {r[3]:8.1f} MB")
    half = [(r[1], r[3]) for r in mapping if r[1] >= scans / 2.0]
    slope = slope_per_1000(half)
    if slope is None or len(half) < 4:
        raise Failure(f"only {len(half)} samples in the second half: too short a run to judge")
    grew = at[-1][1][3] - at[2][1][3]
    print(f"second half: {slope:+.2f} MB per 1,000 scans (least squares over {len(half)} samples; "
          f"RSS {grew:+.1f} MB from 50 % to 100 %)")
    if a.check_flat is not None:
        if slope > a.check_flat:
            print(f"FAIL: RSS grows {slope:.2f} MB per 1,000 scans over the second half, "
                  f"more than the bound of {a.check_flat:g}" +
                  ("" if a.max_blocks else f" (the run's max-blocks: {blocks_setting(a.max_blocks)})"))
            return 1
        print(f"within the bound: {slope:+.2f} <= {a.check_flat:g} MB per 1,000 scans")
    return 0


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGHUP, on_signal)
    try:
        sys.exit(main(sys.argv[1:]))
    except Failure as e:
        print(f"load_test: {e}", file=sys.stderr)
        sys.exit(2)
    except (KeyboardInterrupt, Interrupted) as e:
        print(f"load_test: interrupted ({str(e) or 'SIGINT'}); sarmap stopped", file=sys.stderr)
        sys.exit(130)
