#!/usr/bin/python3
# sarmap's own PyTorch DGCNN (the DGCNN_semseg layout and state_dict names of
# the reference implementation), used as the ground truth the C++ network is
# tested against. It writes the golden fixtures under tests/data/dgcnn/
# (random weights with BN statistics measured on a real-looking block, input
# blocks, expected logits computed in float64) and runs a model on a block.
#
#   /usr/bin/python3 tools/python/dgcnn_reference.py fixtures tests/data/dgcnn
#   /usr/bin/python3 tools/python/dgcnn_reference.py run M.safetensors B.npy out.npy
#   /usr/bin/python3 tools/python/dgcnn_reference.py random-model M.safetensors --channels 6
#   /usr/bin/python3 tools/python/dgcnn_reference.py s3dis-fixture tests/data/dgcnn
import argparse
import os
import sys

import numpy as np
import torch
import torch.nn as nn

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from export_safetensors import DEFAULT_METADATA, read_safetensors, write_safetensors  # noqa: E402


def knn(x, k):
    """x: (B, D, N) -> (B, N, k) neighbour indices; a point is its own neighbour."""
    inner = -2 * torch.matmul(x.transpose(2, 1), x)
    xx = torch.sum(x ** 2, dim=1, keepdim=True)
    neg_dist = -xx - inner - xx.transpose(2, 1)
    return neg_dist.topk(k=k, dim=-1)[1]


def edge_features(x, k, knn_channels=None):
    """x: (B, D, N) -> (B, 2D, N, k) holding [x_j - x_i, x_i]."""
    b, d, n = x.shape
    idx = knn(x if knn_channels is None else x[:, knn_channels], k)
    flat = (idx + torch.arange(b).view(-1, 1, 1) * n).view(-1)
    pts = x.transpose(2, 1).contiguous()
    neighbours = pts.view(b * n, d)[flat].view(b, n, k, d)
    centre = pts.view(b, n, 1, d).expand(-1, -1, k, -1)
    return torch.cat((neighbours - centre, centre), dim=3).permute(0, 3, 1, 2).contiguous()


def _conv2d(cin, cout, bn):
    return nn.Sequential(nn.Conv2d(cin, cout, 1, bias=False), bn, nn.LeakyReLU(0.2))


def _conv1d(cin, cout, bn):
    return nn.Sequential(nn.Conv1d(cin, cout, 1, bias=False), bn, nn.LeakyReLU(0.2))


class DGCNNSemSeg(nn.Module):
    """The reference DGCNN_semseg network; widths are parameters so fixtures stay small."""

    def __init__(self, channels=6, classes=4, emb=1024, k=20, edge=64, head=(512, 256)):
        super().__init__()
        self.k = k
        self.bn1, self.bn2, self.bn3 = nn.BatchNorm2d(edge), nn.BatchNorm2d(edge), nn.BatchNorm2d(edge)
        self.bn4, self.bn5 = nn.BatchNorm2d(edge), nn.BatchNorm2d(edge)
        self.bn6 = nn.BatchNorm1d(emb)
        self.bn7, self.bn8 = nn.BatchNorm1d(head[0]), nn.BatchNorm1d(head[1])
        self.conv1 = _conv2d(2 * channels, edge, self.bn1)
        self.conv2 = _conv2d(edge, edge, self.bn2)
        self.conv3 = _conv2d(2 * edge, edge, self.bn3)
        self.conv4 = _conv2d(edge, edge, self.bn4)
        self.conv5 = _conv2d(2 * edge, edge, self.bn5)
        self.conv6 = _conv1d(3 * edge, emb, self.bn6)
        self.conv7 = _conv1d(emb + 3 * edge, head[0], self.bn7)
        self.conv8 = _conv1d(head[0], head[1], self.bn8)
        self.dp1 = nn.Dropout(0.5)
        self.conv9 = nn.Conv1d(head[1], classes, 1, bias=False)

    def forward(self, x):
        """x: (B, C, N) -> logits (B, classes, N)."""
        n = x.size(2)
        c = x.size(1)
        x = edge_features(x, self.k, knn_channels=slice(c - 3, c))
        x1 = self.conv2(self.conv1(x)).max(dim=-1)[0]
        x = edge_features(x1, self.k)
        x2 = self.conv4(self.conv3(x)).max(dim=-1)[0]
        x = edge_features(x2, self.k)
        x3 = self.conv5(x).max(dim=-1)[0]
        local = torch.cat((x1, x2, x3), dim=1)
        glob = self.conv6(local).max(dim=-1, keepdim=True)[0].repeat(1, 1, n)
        x = self.conv8(self.conv7(torch.cat((glob, local), dim=1)))
        return self.conv9(self.dp1(x))


def model_from_tensors(tensors, k=20):
    """Builds a DGCNNSemSeg whose widths follow the tensor shapes (accepts "module.")."""
    tensors = {name[7:] if name.startswith("module.") else name: t for name, t in tensors.items()}
    channels = tensors["conv1.0.weight"].shape[1] // 2
    edge = tensors["conv1.0.weight"].shape[0]
    emb = tensors["conv6.0.weight"].shape[0]
    head = (tensors["conv7.0.weight"].shape[0], tensors["conv8.0.weight"].shape[0])
    classes = tensors["conv9.weight"].shape[0]
    model = DGCNNSemSeg(channels, classes, emb, k, edge, head)
    state = {name: torch.from_numpy(np.array(t)) for name, t in tensors.items()}
    model.load_state_dict(state, strict=False)
    return model.eval()


def block_features(xyz, rgb, cell_origin, block_size, z_min, z_max):
    """The one definition of a block's input features (C++: engine/semantic/dgcnn/block_features.cpp).

    xyz (M, 3) world coordinates, rgb (M, 3) in [0, 255] or None. Returns
    (M, 6) = [x - cx, y - cy, z, nx, ny, nz] or, with rgb, (M, 9) =
    [x - cx, y - cy, z, r, g, b, nx, ny, nz]; cx, cy is the cell's centre and
    n* normalise within the cell (xy) and the fixed height range (z).
    """
    x0, y0 = cell_origin
    local = np.stack([xyz[:, 0] - (x0 + 0.5 * block_size), xyz[:, 1] - (y0 + 0.5 * block_size), xyz[:, 2]], 1)
    norm = np.stack([(xyz[:, 0] - x0) / block_size, (xyz[:, 1] - y0) / block_size,
                     (xyz[:, 2] - z_min) / (z_max - z_min)], 1)
    parts = [local] if rgb is None else [local, rgb / 255.0]
    return np.concatenate(parts + [norm], 1).astype("<f4")


def synthetic_block(rng, n, unique, cell_origin, with_rgb):
    """A 1 m cell with a floor, a wall and a ramp; `unique` distinct points repeated up to n."""
    x0, y0 = cell_origin
    u = rng.random((unique, 2))
    kind = rng.choice(3, size=unique, p=[0.5, 0.3, 0.2])
    xyz = np.zeros((unique, 3))
    xyz[:, 0] = x0 + u[:, 0]
    xyz[:, 1] = y0 + u[:, 1]
    wall = kind == 1
    xyz[wall, 0] = x0 + 0.7
    xyz[wall, 2] = 1.2 * rng.random(wall.sum())
    ramp = kind == 2
    xyz[ramp, 0] = x0 + 0.4 * u[ramp, 0]
    xyz[ramp, 2] = 0.3 * u[ramp, 1]
    xyz += rng.normal(0.0, 0.004, xyz.shape)
    rgb = None
    if with_rgb:
        palette = np.array([[200, 180, 40], [210, 40, 40], [40, 80, 220]], dtype=float)
        rgb = np.clip(palette[kind] + rng.normal(0, 12, (unique, 3)), 0, 255)
    # Up-sampling repeats whole points: a repeated point has every channel
    # equal, so kNN ties between copies cannot change any result.
    order = np.concatenate([np.arange(unique), rng.integers(0, unique, n - unique)])
    xyz = xyz[order]
    rgb = None if rgb is None else rgb[order]
    z_min, z_max = float(DEFAULT_METADATA["sarmap.z_min"]), float(DEFAULT_METADATA["sarmap.z_max"])
    return block_features(xyz, rgb, cell_origin, 1.0, z_min, z_max)


def randomise(model, rng, calibration_block):
    """Random weights, then BN statistics measured on a real-looking block."""
    gen = torch.Generator().manual_seed(int(rng.integers(1 << 31)))
    for module in model.modules():
        if isinstance(module, (nn.Conv1d, nn.Conv2d)):
            fan_in = module.weight.shape[1]
            module.weight.data = torch.randn(module.weight.shape, generator=gen) * (1.0 / fan_in) ** 0.5
        if isinstance(module, (nn.BatchNorm1d, nn.BatchNorm2d)):
            c = module.num_features
            sign = torch.where(torch.rand(c, generator=gen) < 0.1, -1.0, 1.0)  # some negative scales
            module.weight.data = sign * (0.5 + torch.rand(c, generator=gen))
            module.bias.data = 0.2 * torch.randn(c, generator=gen)
            module.momentum = None  # running stats = the calibration batch's stats
            module.reset_running_stats()
    model.train()
    with torch.no_grad():
        model(torch.from_numpy(calibration_block.T[None].copy()))
    model.eval()


def reference_logits(model, block):
    """float64 forward pass: block (N, C) -> logits (N, classes) as float32."""
    m = model.double()
    with torch.inference_mode():
        out = m(torch.from_numpy(block.astype(np.float64).T[None].copy()))[0].T.numpy()
    model.float()
    return np.ascontiguousarray(out, dtype="<f4")


def knn_margin(model, block):
    """Smallest relative gap between the k-th and (k+1)-th neighbour distance over the three kNNs.

    A tiny gap means float32 rounding could pick another neighbour than the
    float64 reference, so fixtures are checked to be well conditioned.
    """
    m = model.double()
    k = model.k
    gaps = []
    x = torch.from_numpy(block.astype(np.float64).T[None].copy())
    c = x.size(1)

    def gap(f):
        d = torch.cdist(f[0].T, f[0].T) ** 2
        s = d.sort(dim=1)[0]
        scale = s[:, k].clamp_min(1e-12)
        gap = (s[:, k] - s[:, k - 1]) / scale
        # Exact ties come from repeated points, whose features are equal too:
        # whichever is picked gives the same result.
        return float(gap[gap > 0].min())

    with torch.inference_mode():
        gaps.append(gap(x[:, c - 3:]))
        x1 = m.conv2(m.conv1(edge_features(x, k, slice(c - 3, c)))).max(dim=-1)[0]
        gaps.append(gap(x1))
        x2 = m.conv4(m.conv3(edge_features(x1, k))).max(dim=-1)[0]
        gaps.append(gap(x2))
    model.float()
    return gaps


def state_numpy(model):
    return {name: t.detach().numpy().astype("<f4") if t.is_floating_point() else t.numpy()
            for name, t in model.state_dict().items()}


def folded_float32_logits(model, block):
    """float32 logits computed the way sarmap computes them.

    BN folded into the convolutions, each EdgeConv's first convolution split
    into W1 x_j + (W2 - W1) x_i, the global feature's share of conv7 as a bias:
    a second float32 implementation whose rounding differs from PyTorch's.
    """
    def folded(seq):
        conv, bn = seq[0], seq[1]
        w = conv.weight.detach().double().flatten(1)
        s = bn.weight.double() / torch.sqrt(bn.running_var.double() + bn.eps)
        return (w * s[:, None]).float(), (bn.bias.double() - s * bn.running_mean.double()).float()

    def leaky(v):
        return torch.nn.functional.leaky_relu(v, 0.2)

    def edge_conv(x, knn_x, first, second):
        w, bias = folded(first)
        c = x.size(1)
        # Neighbours by exact distances of the float32 features, as sarmap re-ranks them.
        f = knn_x.double()
        d = ((f[:, None, :] - f[None, :, :]) ** 2).sum(-1)
        idx = torch.sort(d, dim=1, stable=True)[1][:, : model.k]
        a = x @ w[:, :c].T
        b = x @ (w[:, c:] - w[:, :c]).T + bias
        e = leaky(a[idx] + b[:, None, :])
        if second is None:
            return e.max(dim=1)[0]
        w2, b2 = folded(second)
        return leaky((e @ w2.T).max(dim=1)[0] + b2)

    with torch.inference_mode():
        x = torch.from_numpy(block.astype(np.float32))
        x1 = edge_conv(x, x[:, -3:], model.conv1, model.conv2)
        x2 = edge_conv(x1, x1, model.conv3, model.conv4)
        x3 = edge_conv(x2, x2, model.conv5, None)
        local = torch.cat((x1, x2, x3), dim=1)
        w6, b6 = folded(model.conv6)
        glob = leaky((local @ w6.T).max(dim=0)[0] + b6)
        w7, b7 = folded(model.conv7)
        emb = glob.numel()
        h = leaky(local @ w7[:, emb:].T + (w7[:, :emb] @ glob + b7))
        w8, b8 = folded(model.conv8)
        h = leaky(h @ w8.T + b8)
        return (h @ model.conv9.weight.detach().flatten(1).T).numpy()


def well_conditioned(model, block, logits):
    """True when float32 rounding, PyTorch's or sarmap's, leaves the logits in place.

    Where two neighbours of a point are within rounding of a tie, either
    answer is right and no test can demand one: such blocks are not fixtures.
    """
    scale = float(logits.max() - logits.min())
    with torch.inference_mode():
        plain = model(torch.from_numpy(block.T[None].copy()))[0].T.numpy()
    return all(np.abs(out - logits).max() <= 2e-4 * scale for out in (plain, folded_float32_logits(model, block)))


def write_fixtures(out_dir):
    rng = np.random.default_rng(20240611)
    os.makedirs(out_dir, exist_ok=True)
    specs = [  # channels, classes, emb, head, class names
        (6, 4, 64, (64, 32), "terrain,wall,inclined_ramp,flat_ramp"),
        (9, 5, 96, (48, 32), "terrain,wall,inclined_ramp,flat_ramp,other"),
    ]
    for channels, classes, emb, head, names in specs:
        for attempt in range(10):
            torch.manual_seed(channels * 100 + attempt)
            model = DGCNNSemSeg(channels, classes, emb, 20, 64, head)
            blocks = {n: synthetic_block(rng, n, int(n * 0.8), (3.0, -2.0), channels == 9) for n in (4096, 1024)}
            randomise(model, rng, blocks[4096])
            logits = {n: reference_logits(model, block) for n, block in blocks.items()}
            if all(well_conditioned(model, blocks[n], logits[n]) for n in blocks):
                break
            print(f"C={channels}: attempt {attempt} has a near-tie that decides a logit; drawing again")
        else:
            raise RuntimeError("no well-conditioned fixture found")
        metadata = dict(DEFAULT_METADATA)
        metadata["sarmap.classes"] = names
        write_safetensors(os.path.join(out_dir, f"model_c{channels}.safetensors"), state_numpy(model), metadata)
        for n, block in blocks.items():
            np.save(os.path.join(out_dir, f"block_c{channels}_n{n}.npy"), block)
            np.save(os.path.join(out_dir, f"logits_c{channels}_n{n}.npy"), logits[n])
            print(f"C={channels} N={n}: logit range {logits[n].min():.3f}..{logits[n].max():.3f}, "
                  f"kNN relative margins {['%.1e' % g for g in knn_margin(model, block)]}")


def write_feature_fixture(out_dir):
    """features_points.npy: (M, 6) float32 x, y, z, r, g, b of points in the cell
    at FEATURE_ORIGIN (size 1 m); features_c6/c9.npy: block_features of them."""
    rng = np.random.default_rng(11)
    m = 200
    pts = np.zeros((m, 6), dtype="<f4")
    pts[:, 0] = FEATURE_ORIGIN[0] + rng.random(m)
    pts[:, 1] = FEATURE_ORIGIN[1] + rng.random(m)
    pts[:, 2] = rng.uniform(-0.4, 2.4, m)
    pts[:, 3:] = rng.integers(0, 256, (m, 3))
    xyz, rgb = pts[:, :3].astype(np.float64), pts[:, 3:].astype(np.float64)
    z_min, z_max = float(DEFAULT_METADATA["sarmap.z_min"]), float(DEFAULT_METADATA["sarmap.z_max"])
    block = float(DEFAULT_METADATA["sarmap.block_size"])
    os.makedirs(out_dir, exist_ok=True)
    np.save(os.path.join(out_dir, "features_points.npy"), pts)
    np.save(os.path.join(out_dir, "features_c6.npy"), block_features(xyz, None, FEATURE_ORIGIN, block, z_min, z_max))
    np.save(os.path.join(out_dir, "features_c9.npy"), block_features(xyz, rgb, FEATURE_ORIGIN, block, z_min, z_max))


FEATURE_ORIGIN = (2.0, -3.0)

# The 13 classes of the DGCNN authors' S3DIS model, in its logit order.
S3DIS_CLASSES = "ceiling,floor,wall,beam,column,window,door,table,chair,sofa,bookcase,board,clutter"


def write_s3dis_fixture(out_dir):
    """model_s3dis13.safetensors: a tiny random model with the authors' S3DIS
    class names (their weights are not available here), to test that a model
    with another class list loads and maps onto sarmap's classes."""
    rng = np.random.default_rng(13)
    torch.manual_seed(13)
    model = DGCNNSemSeg(6, 13, 32, 20, 16, (32, 16))
    block = synthetic_block(rng, 1024, 900, (0.0, 0.0), False)
    randomise(model, rng, block)
    metadata = dict(DEFAULT_METADATA)
    metadata["sarmap.points_per_block"] = "1024"
    metadata["sarmap.classes"] = S3DIS_CLASSES
    os.makedirs(out_dir, exist_ok=True)
    write_safetensors(os.path.join(out_dir, "model_s3dis13.safetensors"), state_numpy(model), metadata)
    winners = np.bincount(reference_logits(model, block).argmax(1), minlength=13)
    print(f"S3DIS fixture: arg-max counts per logit on a synthetic block {winners.tolist()}")


def main(argv):
    parser = argparse.ArgumentParser(description="sarmap's reference DGCNN")
    sub = parser.add_subparsers(dest="command", required=True)
    fx = sub.add_parser("fixtures", help="write the golden fixtures")
    fx.add_argument("out_dir")
    run = sub.add_parser("run", help="run a .safetensors model on an (N, C) .npy block")
    run.add_argument("model")
    run.add_argument("block")
    run.add_argument("logits")
    ft = sub.add_parser("features", help="write points + their expected block features (C++ feature test)")
    ft.add_argument("out_dir")
    s3 = sub.add_parser("s3dis-fixture", help="write a tiny random model with the S3DIS class names")
    s3.add_argument("out_dir")
    rnd = sub.add_parser("random-model", help="a full-size random model (benchmarks)")
    rnd.add_argument("model")
    rnd.add_argument("--channels", type=int, default=6)
    rnd.add_argument("--classes", type=int, default=4)
    rnd.add_argument("--emb", type=int, default=1024)
    rnd.add_argument("--k", type=int, default=20)
    rnd.add_argument("--head", default="512,256", help="widths of conv7 and conv8")
    rnd.add_argument("--points", type=int, default=4096, help="points per block")
    rnd.add_argument("--block", help="also write a synthetic block of --points points here")
    args = parser.parse_args(argv)

    if args.command == "fixtures":
        write_fixtures(args.out_dir)
    elif args.command == "s3dis-fixture":
        write_s3dis_fixture(args.out_dir)
    elif args.command == "features":
        write_feature_fixture(args.out_dir)
    elif args.command == "run":
        tensors, metadata = read_safetensors(args.model)
        model = model_from_tensors(tensors, int(metadata.get("sarmap.k", 20)))
        np.save(args.logits, reference_logits(model, np.load(args.block)))
    else:
        rng = np.random.default_rng(7)
        head = tuple(int(w) for w in args.head.split(","))
        model = DGCNNSemSeg(args.channels, args.classes, args.emb, args.k, 64, head)
        block = synthetic_block(rng, args.points, args.points * 7 // 8, (0.0, 0.0), args.channels == 9)
        randomise(model, rng, block)
        metadata = dict(DEFAULT_METADATA)
        metadata["sarmap.k"] = str(args.k)
        metadata["sarmap.points_per_block"] = str(args.points)
        names = ["terrain", "wall", "inclined_ramp", "flat_ramp", "other"]
        if not 1 <= args.classes <= len(names):
            parser.error(f"--classes must be 1..{len(names)}")
        metadata["sarmap.classes"] = ",".join(names[: args.classes])
        write_safetensors(args.model, state_numpy(model), metadata)
        if args.block:
            np.save(args.block, block)


if __name__ == "__main__":
    main(sys.argv[1:])
