#!/usr/bin/python3
# Trains sarmap's ramp DGCNN on blocks cut from simulated arenas
# (training_blocks.py) and exports it as the .safetensors file the C++
# engine reads, with every preprocessing setting in its metadata.
#
# Runs on the CPU with Debian's python3-torch. It checkpoints after every
# epoch (WORK/checkpoint.pt, written atomically) and resumes from it when run
# again with the same WORK folder, so a long run can span several sittings.
#
#   MALLOC_MMAP_MAX_=0 MALLOC_TRIM_THRESHOLD_=68719476736 \
#   /usr/bin/python3 tools/python/train_dgcnn.py train --data blocks.npz --val-data val.npz --work /tmp/run
#   /usr/bin/python3 tools/python/train_dgcnn.py export --work /tmp/run --out datasets/models/ramps-dgcnn.safetensors
import argparse
import json
import math
import os
import sys
import time

import numpy as np
import torch
import torch.nn.functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dgcnn_reference import DGCNNSemSeg, block_features, state_numpy  # noqa: E402
from export_safetensors import DEFAULT_METADATA, read_safetensors, write_safetensors  # noqa: E402

# Logit index -> sarmap class (engine/core/classes.hpp ids 1..5); id 0 (unknown) is ignored.
CLASSES = ["terrain", "wall", "inclined_ramp", "flat_ramp", "other"]
IGNORE = -100


class Blocks:
    """The blocks of one training_blocks.py file."""

    def __init__(self, path):
        data = np.load(path)
        self.points, self.labels, self.offsets = data["points"], data["labels"], data["offsets"]
        self.origins, self.arena = data["origins"], data["arena"]
        self.block_size = float(data["block_size"])
        # sarmap ids 1..5 -> logits 0..4, unknown -> ignored.
        self.targets = np.where(self.labels == 0, IGNORE, self.labels.astype(np.int64) - 1)

    def __len__(self):
        return len(self.origins)

    def class_fractions(self, b):
        lab = self.labels[self.offsets[b]:self.offsets[b + 1]]
        return np.bincount(lab, minlength=6)[1:] / max(1, len(lab))

    def sample(self, b, points, rng, augment, z_range):
        """(points, C) features and (points,) targets of block b, as the C++ engine samples it."""
        lo, hi = self.offsets[b], self.offsets[b + 1]
        count = hi - lo
        if count >= points:
            pick = rng.choice(count, points, replace=False)
        else:  # every point once, then random repeats (engine/semantic/dgcnn/block_sampling.hpp)
            pick = np.concatenate([np.arange(count), rng.integers(0, count, points - count)])
        xyz = self.points[lo + pick].astype(np.float64)
        origin = self.origins[b]
        if augment:
            xyz = augmented(xyz, origin, self.block_size, rng)
        features = block_features(xyz, None, origin, self.block_size, *z_range)
        return features, self.targets[lo + pick]


def augmented(xyz, origin, block_size, rng):
    """A symmetry of the cell (quarter turns about z, mirror), small scaling and jitter.

    Quarter turns and mirrors keep every point inside its cell, so the
    normalised coordinates stay in the range the engine produces; arbitrary
    yaws are already in the data (the arena generator rotates everything).
    """
    centre = np.array([origin[0] + 0.5 * block_size, origin[1] + 0.5 * block_size])
    xy = xyz[:, :2] - centre
    for _ in range(rng.integers(4)):
        xy = np.stack([-xy[:, 1], xy[:, 0]], 1)
    if rng.random() < 0.5:
        xy[:, 0] = -xy[:, 0]
    xy *= rng.uniform(0.95, 1.05)
    out = np.empty_like(xyz)
    out[:, :2] = xy + centre
    out[:, 2] = xyz[:, 2] * rng.uniform(0.95, 1.05)
    return out + np.clip(rng.normal(0.0, 0.003, xyz.shape), -0.01, 0.01)


def class_weights(blocks, ramp_boost):
    """Per-block draw weights (blocks with ramps or obstacles drawn more often) and loss weights."""
    fractions = np.stack([blocks.class_fractions(b) for b in range(len(blocks))])
    rare = fractions[:, 2:].sum(1)  # inclined ramp, flat ramp, other
    draw = 1.0 + ramp_boost * (rare > 0.05)
    draw /= draw.sum()
    frequency = (fractions * draw[:, None]).sum(0)
    loss = np.sqrt(np.median(frequency) / np.maximum(frequency, 1e-6))
    return draw, loss.astype(np.float32)


def confusion(pred, target, classes):
    keep = target != IGNORE
    return np.bincount(target[keep] * classes + pred[keep], minlength=classes * classes).reshape(classes, classes)


def iou(conf):
    tp = np.diag(conf).astype(np.float64)
    denom = conf.sum(0) + conf.sum(1) - tp
    return np.where(denom > 0, tp / np.maximum(denom, 1), np.nan)


def evaluate(model, blocks, args, z_range):
    rng = np.random.default_rng(99)
    conf = np.zeros((len(CLASSES), len(CLASSES)), dtype=np.int64)
    chosen = rng.choice(len(blocks), min(args.val_blocks, len(blocks)), replace=False)
    model.eval()
    with torch.inference_mode():
        for start in range(0, len(chosen), args.batch):
            batch = [blocks.sample(b, args.points, rng, False, z_range) for b in chosen[start:start + args.batch]]
            x = torch.from_numpy(np.stack([f.T for f, _ in batch]))
            pred = model(x).argmax(1).numpy()
            for p, (_, t) in zip(pred, batch):
                conf += confusion(p, t, len(CLASSES))
    return conf


def weights_from_model(model, path):
    """Loads an exported model's weights into `model`; returns its training record for the metadata.

    A shipped .safetensors file is the one trace of a run whose checkpoint is
    gone, so a new sitting can start from it. The widths must match; the block
    size and points per block may differ (the network's weights do not depend
    on them), which is how a model is carried over to larger blocks.
    """
    tensors, metadata = read_safetensors(path)
    state = model.state_dict()
    for name, array in tensors.items():
        if name not in state:
            raise SystemExit(f"{path}: tensor {name} is not in this network (other widths?)")
        if tuple(state[name].shape) != tuple(array.shape):
            raise SystemExit(f"{path}: {name} has shape {tuple(array.shape)}, this network {tuple(state[name].shape)}")
    missing = [n for n in state if n not in tensors and not n.endswith("num_batches_tracked")]
    if missing:
        raise SystemExit(f"{path}: lacks {', '.join(missing)}")
    model.load_state_dict({n: torch.from_numpy(np.array(a)) for n, a in tensors.items()}, strict=False)
    record = json.loads(metadata.get("sarmap.training", "null")) or {}
    record["model"] = os.path.basename(path)
    record["block_size"] = float(metadata.get("sarmap.block_size", "1.0"))
    record["points_per_block"] = int(metadata.get("sarmap.points_per_block", "0"))
    return record


def save_checkpoint(path, state):
    tmp = path + ".tmp"
    torch.save(state, tmp)
    os.replace(tmp, path)


def train(args):
    torch.set_num_threads(args.threads)
    os.makedirs(args.work, exist_ok=True)
    config_path = os.path.join(args.work, "config.json")
    config = {k: getattr(args, k) for k in ("data", "val_data", "points", "k", "emb", "head", "batch", "epochs",
                                            "steps_per_epoch", "lr", "seed", "ramp_boost", "init_from")}
    if os.path.exists(config_path):
        with open(config_path) as f:
            saved = json.load(f)
        if saved != config:
            raise SystemExit(f"{args.work} holds a run with other settings ({saved}); use another --work")
    else:
        with open(config_path, "w") as f:
            json.dump(config, f, indent=1)

    z_range = (float(DEFAULT_METADATA["sarmap.z_min"]), float(DEFAULT_METADATA["sarmap.z_max"]))
    blocks, val = Blocks(args.data), Blocks(args.val_data)
    draw, loss_weights = class_weights(blocks, args.ramp_boost)
    print(f"{len(blocks)} training blocks, {len(val)} validation blocks; loss weights {np.round(loss_weights, 2)}")

    torch.manual_seed(args.seed)
    head = tuple(int(w) for w in args.head.split(","))
    model = DGCNNSemSeg(6, len(CLASSES), args.emb, args.k, 64, head)
    optimiser = torch.optim.Adam(model.parameters(), lr=args.lr, weight_decay=1e-4)
    total_steps = args.epochs * args.steps_per_epoch
    schedule = torch.optim.lr_scheduler.LambdaLR(
        optimiser, lambda step: 0.02 + 0.98 * 0.5 * (1 + math.cos(math.pi * min(step, total_steps) / total_steps)))
    checkpoint_path = os.path.join(args.work, "checkpoint.pt")
    epoch, history, history_before = 0, [], None
    if os.path.exists(checkpoint_path):
        state = torch.load(checkpoint_path)
        model.load_state_dict(state["model"])
        optimiser.load_state_dict(state["optimiser"])
        schedule.load_state_dict(state["schedule"])
        epoch, history = state["epoch"], state["history"]
        history_before = state.get("history_before")
        print(f"resuming after epoch {epoch}")
    elif args.init_from and args.init_from.endswith(".safetensors"):
        history_before = weights_from_model(model, args.init_from)
        print(f"starting from the weights of {args.init_from}")
    elif args.init_from:
        # A fresh schedule over weights trained before: a warm restart, e.g.
        # on more arenas. The earlier run's history is kept for the metadata.
        prior = torch.load(args.init_from)
        model.load_state_dict(prior["model"])
        with open(os.path.join(os.path.dirname(args.init_from), "config.json")) as f:
            prior_config = json.load(f)
        prior_data = np.load(prior_config["data"])
        history_before = {"epochs": prior["epoch"], "data": prior_config["data"],
                          "arena_seeds": sorted(set(int(s) for s in prior_data["arena"])),
                          "train_seconds": round(sum(h["seconds"] for h in prior["history"])),
                          "before": prior.get("history_before")}
        print(f"starting from {args.init_from} (after its epoch {prior['epoch']})")
    weights = torch.from_numpy(loss_weights)

    while epoch < args.epochs:
        # Each epoch's draws depend only on (seed, epoch), so a resumed run repeats an uninterrupted one.
        rng = np.random.default_rng([args.seed, epoch])
        torch.manual_seed(args.seed * 1000 + epoch)
        model.train()
        started, losses = time.time(), []
        for step in range(args.steps_per_epoch):
            chosen = rng.choice(len(blocks), args.batch, p=draw)
            batch = [blocks.sample(b, args.points, rng, True, z_range) for b in chosen]
            x = torch.from_numpy(np.stack([f.T for f, _ in batch]))
            y = torch.from_numpy(np.stack([t for _, t in batch]))
            loss = F.cross_entropy(model(x), y, weight=weights, ignore_index=IGNORE)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
            losses.append(float(loss))
            if (step + 1) % 20 == 0:
                print(f"epoch {epoch + 1} step {step + 1}: loss {np.mean(losses[-20:]):.4f}, "
                      f"{(time.time() - started) / (step + 1):.2f} s/step", flush=True)
        epoch += 1
        conf = evaluate(model, val, args, z_range)
        per_class = iou(conf)
        record = {"epoch": epoch, "loss": float(np.mean(losses)), "seconds": time.time() - started,
                  "val_accuracy": float(np.trace(conf) / max(1, conf.sum())),
                  # None where a class is absent from the validation draw (JSON has no NaN).
                  "val_iou": {c: None if np.isnan(v) else float(v) for c, v in zip(CLASSES, per_class)},
                  "val_mean_iou_4": float(np.nanmean(per_class[:4]))}
        history.append(record)
        print(json.dumps(record), flush=True)
        save_checkpoint(checkpoint_path, {"model": model.state_dict(), "optimiser": optimiser.state_dict(),
                                          "schedule": schedule.state_dict(), "epoch": epoch,
                                          "history": history, "history_before": history_before,
                                          "confusion": conf.tolist()})
    print("training done")


def export(args):
    with open(os.path.join(args.work, "config.json")) as f:
        config = json.load(f)
    state = torch.load(os.path.join(args.work, "checkpoint.pt"))
    head = tuple(int(w) for w in config["head"].split(","))
    model = DGCNNSemSeg(6, len(CLASSES), config["emb"], config["k"], 64, head)
    model.load_state_dict(state["model"])
    data = np.load(config["data"])
    last = state["history"][-1]
    metadata = dict(DEFAULT_METADATA)
    metadata.update({
        "sarmap.k": str(config["k"]),
        "sarmap.points_per_block": str(config["points"]),
        "sarmap.block_size": str(float(data["block_size"])),
        "sarmap.classes": ",".join(CLASSES),
        "sarmap.training": json.dumps({
            "arena_seeds": sorted(set(int(s) for s in data["arena"])),
            "validation_arena_seeds": sorted(set(int(s) for s in np.load(config["val_data"])["arena"])),
            "seed": config["seed"], "epochs": state["epoch"], "steps_per_epoch": config["steps_per_epoch"],
            "batch": config["batch"], "lr": config["lr"], "emb": config["emb"], "head": config["head"],
            "val_accuracy": round(last["val_accuracy"], 4), "val_mean_iou_4": round(last["val_mean_iou_4"], 4),
            "val_iou": {c: None if v is None else round(v, 4) for c, v in last["val_iou"].items()},
            "train_seconds": round(sum(h["seconds"] for h in state["history"])),
            "data": blocks_record(data),
            # Set when this run started from another's weights (--init-from).
            "fine_tuned_from": state.get("history_before"),
        }, separators=(",", ":")),
    })
    tensors = {name: t for name, t in state_numpy(model).items() if not name.endswith("num_batches_tracked")}
    write_safetensors(args.out, tensors, metadata)
    print(f"wrote {args.out}: {metadata['sarmap.training']}")


def blocks_record(data):
    """What the training blocks were (training_blocks.py, join_blocks.py): their count, sensors, how many
    sensor mountings and whether they were cut from frames or from accumulated maps."""
    record = {"blocks": int(len(data["arena"]))}
    if "block_sensor" in data:
        sensors, counts = np.unique(data["block_sensor"].astype(str), return_counts=True)
        record["sensors"] = {str(s): int(c) for s, c in zip(sensors, counts)}
    elif "sensor" in data:
        record["sensors"] = {str(data["sensor"]): record["blocks"]}
    if "map_cell" in data and float(data["map_cell"]) > 0:
        record["map_cell"] = float(data["map_cell"])
        record["snapshots"] = int(data["snapshots"])
    if "block_mount" in data:
        # How many sensor mountings (sarmap simulate options) the blocks were seen with.
        record["mountings"] = int(len(np.unique(data["block_mount"].astype(str))))
    return record


def main(argv):
    parser = argparse.ArgumentParser(description="train sarmap's ramp DGCNN")
    sub = parser.add_subparsers(dest="command", required=True)
    tr = sub.add_parser("train", help="train (resumes from WORK/checkpoint.pt)")
    tr.add_argument("--data", required=True, help="training blocks (training_blocks.py)")
    tr.add_argument("--val-data", required=True, help="validation blocks from other arenas")
    tr.add_argument("--work", required=True, help="folder for config, checkpoint and log")
    tr.add_argument("--points", type=int, default=1024, help="points per block")
    tr.add_argument("--k", type=int, default=16)
    tr.add_argument("--emb", type=int, default=512)
    tr.add_argument("--head", default="512,256", help="widths of conv7 and conv8")
    tr.add_argument("--batch", type=int, default=8)
    tr.add_argument("--epochs", type=int, default=16)
    tr.add_argument("--steps-per-epoch", type=int, default=200)
    tr.add_argument("--lr", type=float, default=1e-3)
    tr.add_argument("--seed", type=int, default=1)
    tr.add_argument("--ramp-boost", type=float, default=3.0, help="extra draw weight of blocks with ramps/obstacles")
    tr.add_argument("--val-blocks", type=int, default=160)
    tr.add_argument("--threads", type=int, default=1)
    tr.add_argument("--init-from", help="start from the weights of another run's checkpoint.pt or of an exported "
                    ".safetensors model (new schedule)")
    ex = sub.add_parser("export", help="write the trained model as .safetensors with sarmap metadata")
    ex.add_argument("--work", required=True)
    ex.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    train(args) if args.command == "train" else export(args)


if __name__ == "__main__":
    main(sys.argv[1:])
