#!/usr/bin/python3
# The per-point accuracy table of sarmap's classifiers on held-out arenas:
# simulates each arena (random arenas from seeds never used in training, plus
# the shipped arenas), runs `sarmap run` with each classifier and scores the
# run with `sarmap eval`, then prints per-class IoU per arena and overall and
# the overall confusion matrices, as Markdown.
#
#   /usr/bin/python3 tools/python/eval_classifiers.py --sarmap build/release/tools/sarmap/sarmap \
#       --work /tmp/sarmap-eval --random 9001-9005 --arena datasets/arenas/esogu-6x4.json \
#       --arena datasets/arenas/building-52x15.json --every 4
#
# --sensor lidar (and --sensor-args) sees the random arenas with another
# sensor (`sarmap simulate --random SEED --sensor ...`); their sequences are
# cached apart from the depth camera's.
import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys

import numpy as np

CLASSES = ["unknown", "terrain", "wall", "inclined_ramp", "flat_ramp", "other"]
MAPPING = CLASSES[1:5]  # the four mapping classes the mean IoU is taken over


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def thin_sequence(folder, every):
    """Keeps every n-th frame of a simulated sequence (neighbouring frames overlap heavily)."""
    path = os.path.join(folder, "sequence.json")
    with open(path) as f:
        manifest = json.load(f)
    kept = manifest["frames"][::every]
    for frame in manifest["frames"]:
        if frame not in kept:
            os.remove(os.path.join(folder, frame["file"]))
    manifest["frames"] = kept
    with open(path, "w") as f:
        json.dump(manifest, f, indent=1)


def simulate(sarmap, work, name, arena_json, seed, every, sensor_args):
    """Returns (arena JSON path, sequence folder); cached in WORK (simulated again when the command or --every
    differs from the cached one's)."""
    folder = os.path.join(work, name, "sequence")
    arena_path = arena_json or os.path.join(work, name, "arena.json")
    cmd = [sarmap, "simulate", "--out", folder, "--quiet", "--seed", "7"]
    cmd += ["--random", str(seed), "--write-arena", arena_path] + sensor_args if arena_json is None else [arena_json]
    stamp_path = os.path.join(work, name, "simulated.json")
    stamp = {"command": cmd[1:], "every": every}
    cached = os.path.exists(os.path.join(folder, "sequence.json")) and os.path.exists(stamp_path)
    if cached:
        with open(stamp_path) as f:
            cached = json.load(f) == stamp
    if not cached:
        shutil.rmtree(folder, ignore_errors=True)
        os.makedirs(os.path.dirname(folder), exist_ok=True)
        run(cmd)
        thin_sequence(folder, every)
        with open(stamp_path, "w") as f:
            json.dump(stamp, f)
    return arena_path, folder


def evaluate(sarmap, work, name, arena_path, folder, classifier, model, min_block_points, block_stride,
             disabled_rules, threads):
    # "dgcnn-per-scan": the network on every scan instead of the accumulated map.
    base = "dgcnn" if classifier.startswith("dgcnn") else classifier
    suffix = ""
    if base == "dgcnn":
        suffix = (f"-stride{block_stride}" if block_stride else "") + "".join(f"-no-{r}" for r in sorted(disabled_rules))
    out = os.path.join(work, name, classifier + suffix)
    cmd = [sarmap, "run", folder, "--out", out, "--classifier", base, "--quiet", "--threads", str(threads)]
    if classifier == "dgcnn-per-scan":
        cmd += ["--classify-per-scan"]
    if base == "dgcnn" and model:
        cmd += ["--model", model]
    if base == "dgcnn" and min_block_points:
        cmd += ["--min-block-points", str(min_block_points)]
    if base == "dgcnn" and block_stride:
        cmd += ["--block-stride", str(block_stride)]
    if base == "dgcnn":
        for rule in disabled_rules:
            cmd += ["--disable-rule", rule]
    run(cmd)
    result = json.loads(run([sarmap, "eval", "--arena", arena_path, "--run", out, "--json"]))
    with open(os.path.join(out, "profile.json")) as f:
        profile = json.load(f)
    classify = profile["stages"].get("classify", {})
    return np.array(result["confusion"]["matrix"], dtype=np.int64), classify.get("mean_s")


def ious(conf):
    tp = np.diag(conf).astype(np.float64)
    denom = conf.sum(0) + conf.sum(1) - tp
    return {c: (tp[i] / denom[i] if denom[i] > 0 else None) for i, c in enumerate(CLASSES) if i > 0}


def mean_iou(per_class):
    values = [per_class[c] for c in MAPPING if per_class[c] is not None]
    return sum(values) / len(values) if values else None


def pct(v):
    return "–" if v is None else f"{100 * v:.1f}"


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        a, _, b = part.partition("-")
        seeds.extend(range(int(a), int(b or a) + 1))
    return seeds


def main(argv):
    parser = argparse.ArgumentParser(description="per-point classifier accuracy on held-out arenas")
    parser.add_argument("--sarmap", required=True)
    parser.add_argument("--work", required=True, help="folder for sequences and runs (sequences are cached)")
    parser.add_argument("--random", default="", help="seeds of generated arenas, e.g. 9001-9005")
    parser.add_argument("--arena", action="append", default=[], help="arena JSON files")
    parser.add_argument("--classifier", action="append", default=None,
                        help="dgcnn (the accumulated map), dgcnn-per-scan, geometric or labels; "
                             "default: dgcnn and geometric")
    parser.add_argument("--model", help="DGCNN model (default: the shipped one)")
    parser.add_argument("--min-block-points", type=int, help="passed to sarmap run (default: its own)")
    parser.add_argument("--block-stride", type=float, help="passed to sarmap run: overlapping DGCNN blocks")
    parser.add_argument("--disable-rule", action="append", default=[], metavar="NAME",
                        help="passed to sarmap run for the DGCNN runs (repeatable): ramp_veto, wall_bands, "
                             "ramp_sides or wall_feet")
    parser.add_argument("--every", type=int, default=4, help="use every n-th frame")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--sensor", choices=["depth", "lidar"], default="depth",
                        help="the random arenas' sensor (sarmap simulate --sensor; the arena files keep theirs)")
    parser.add_argument("--sensor-args", default="",
                        help="more options for sarmap simulate, e.g. \"--rings 16 --min-range 0.4 --max-range 12\"")
    args = parser.parse_args(argv)
    classifiers = args.classifier or ["dgcnn", "geometric"]
    sensor_args = shlex.split(args.sensor_args)
    if args.sensor != "depth" or sensor_args:
        sensor_args = ["--sensor", args.sensor] + sensor_args
    # Sequences of another sensor are cached under their own name.
    tag = "" if not sensor_args else "-" + args.sensor
    arenas = [(f"random-{s}{tag}", None, s) for s in parse_seeds(args.random)] if args.random else []
    arenas += [(os.path.splitext(os.path.basename(a))[0], os.path.abspath(a), None) for a in args.arena]

    totals = {c: np.zeros((len(CLASSES), len(CLASSES)), dtype=np.int64) for c in classifiers}
    rows = []
    for name, arena_json, seed in arenas:
        arena_path, folder = simulate(args.sarmap, args.work, name, arena_json, seed, args.every, sensor_args)
        for classifier in classifiers:
            conf, classify_s = evaluate(args.sarmap, args.work, name, arena_path, folder, classifier, args.model,
                                        args.min_block_points, args.block_stride, args.disable_rule, args.threads)
            totals[classifier] += conf
            rows.append((name, classifier, ious(conf), classify_s))
            print(f"{name} {classifier}: mean IoU {pct(mean_iou(rows[-1][2]))}", file=sys.stderr, flush=True)

    header = "| arena | classifier | " + " | ".join(CLASSES[1:]) + " | mean IoU (4 mapping classes) | classify s/scan |"
    print(header)
    print("|" + "---|" * (len(CLASSES) + 3))
    for name, classifier, per_class, classify_s in rows + [("**all**", c, ious(totals[c]), None) for c in classifiers]:
        cells = " | ".join(pct(per_class[c]) for c in CLASSES[1:])
        seconds = "" if classify_s is None else f"{classify_s:.3f}"
        print(f"| {name} | {classifier} | {cells} | {pct(mean_iou(per_class))} | {seconds} |")
    for classifier in classifiers:
        conf = totals[classifier]
        print(f"\nConfusion, {classifier}, all arenas (rows ground truth, columns prediction, % of the row):\n")
        print("| truth \\ predicted | " + " | ".join(CLASSES) + " |")
        print("|" + "---|" * (len(CLASSES) + 1))
        for i, c in enumerate(CLASSES):
            total = conf[i].sum()
            if total == 0:
                continue
            print(f"| {c} | " + " | ".join(f"{100 * v / total:.1f}" for v in conf[i]) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
