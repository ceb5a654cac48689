#!/usr/bin/python3
# Writes safetensors files without the safetensors package (Debian has none):
# an 8-byte little-endian header length, a JSON header, then raw little-endian
# tensor data. Run as a script it converts a reference-code DGCNN checkpoint
# (a PyTorch state_dict, optionally wrapped or "module."-prefixed) into the
# .safetensors file `sarmap classify --model` reads, with sarmap's metadata.
#
#   /usr/bin/python3 tools/python/export_safetensors.py model.t7 model.safetensors \
#       --classes terrain,wall,inclined_ramp,flat_ramp --k 20
#
# A model trained on other classes keeps its own names; sarmap maps them onto
# its classes (docs/formats.md, "Model file"), e.g. the DGCNN authors' S3DIS model:
#
#   ... --classes ceiling,floor,wall,beam,column,window,door,table,chair,sofa,bookcase,board,clutter \
#       --class-map door=other,board=wall
import argparse
import json
import struct
import sys

import numpy as np

# numpy dtype -> safetensors dtype name.
_DTYPES = {
    np.dtype("<f4"): "F32",
    np.dtype("<f8"): "F64",
    np.dtype("<f2"): "F16",
    np.dtype("<i8"): "I64",
    np.dtype("<i4"): "I32",
    np.dtype("uint8"): "U8",
}

# The normalisation every sarmap model is trained with (see block_features in
# dgcnn_reference.py and engine/semantic/dgcnn/block_features.hpp): x and y relative
# to the block's own cell, z over a fixed height range in the world frame.
DEFAULT_METADATA = {
    "sarmap.k": "20",
    "sarmap.points_per_block": "4096",
    "sarmap.block_size": "1.0",
    "sarmap.normalisation": "cell_xy_fixed_z",
    "sarmap.z_min": "-0.5",
    "sarmap.z_max": "2.5",
}


def write_safetensors(path, tensors, metadata=None):
    """tensors: dict name -> numpy array (written in little-endian, C order)."""
    header = {}
    blobs = []
    offset = 0
    for name, array in tensors.items():
        array = np.ascontiguousarray(array)
        dtype = array.dtype.newbyteorder("<") if array.dtype.byteorder == ">" else array.dtype
        if dtype not in _DTYPES:
            raise ValueError(f"{name}: dtype {array.dtype} has no safetensors name")
        data = array.astype(dtype, copy=False).tobytes()
        header[name] = {
            "dtype": _DTYPES[dtype],
            "shape": list(array.shape),
            "data_offsets": [offset, offset + len(data)],
        }
        blobs.append(data)
        offset += len(data)
    if metadata:
        header["__metadata__"] = {str(k): str(v) for k, v in metadata.items()}
    text = json.dumps(header, separators=(",", ":")).encode("utf-8")
    text += b" " * ((8 - len(text) % 8) % 8)  # keeps the data 8-byte aligned
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)))
        f.write(text)
        for blob in blobs:
            f.write(blob)


def read_safetensors(path):
    """Returns (dict name -> numpy array, metadata dict)."""
    with open(path, "rb") as f:
        raw = f.read()
    (length,) = struct.unpack("<Q", raw[:8])
    header = json.loads(raw[8 : 8 + length])
    metadata = header.pop("__metadata__", {})
    inverse = {v: k for k, v in _DTYPES.items()}
    data = raw[8 + length :]
    tensors = {}
    for name, entry in header.items():
        begin, end = entry["data_offsets"]
        tensors[name] = np.frombuffer(data[begin:end], dtype=inverse[entry["dtype"]]).reshape(entry["shape"])
    return tensors, metadata


def state_dict_to_numpy(state):
    """A reference-code checkpoint -> dict of numpy arrays (floats as float32)."""
    for key in ("model_state_dict", "state_dict", "model"):
        if isinstance(state, dict) and key in state and isinstance(state[key], dict):
            state = state[key]
    out = {}
    for name, tensor in state.items():
        array = tensor.detach().cpu().numpy()
        if np.issubdtype(array.dtype, np.floating):
            array = array.astype("<f4")
        out[name] = array
    return out


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("checkpoint", help="PyTorch state_dict (.pth / .t7) of a DGCNN_semseg model")
    parser.add_argument("output", help="the .safetensors file to write")
    parser.add_argument("--k", default=DEFAULT_METADATA["sarmap.k"])
    parser.add_argument("--points-per-block", default=DEFAULT_METADATA["sarmap.points_per_block"])
    parser.add_argument("--block-size", default=DEFAULT_METADATA["sarmap.block_size"])
    parser.add_argument("--z-min", default=DEFAULT_METADATA["sarmap.z_min"])
    parser.add_argument("--z-max", default=DEFAULT_METADATA["sarmap.z_max"])
    parser.add_argument("--classes", default="terrain,wall,inclined_ramp,flat_ramp",
                        help="the model's class name of each logit, comma separated (any names)")
    parser.add_argument("--class-map", default="",
                        help="NAME=SARMAP_CLASS,... where a name's default sarmap class is not wanted "
                             "(default: a sarmap name itself, floor and ground terrain, any other name other)")
    args = parser.parse_args(argv)
    class_map = {}
    for item in filter(None, args.class_map.split(",")):
        name, sep, target = item.partition("=")
        if not sep or name not in args.classes.split(","):
            parser.error(f"--class-map {item!r}: expected NAME=CLASS with NAME one of --classes")
        class_map[name] = target

    import torch  # only the conversion needs torch

    state = torch.load(args.checkpoint, map_location="cpu")
    metadata = dict(DEFAULT_METADATA)
    metadata.update({
        "sarmap.k": str(args.k),
        "sarmap.points_per_block": str(args.points_per_block),
        "sarmap.block_size": str(args.block_size),
        "sarmap.z_min": str(args.z_min),
        "sarmap.z_max": str(args.z_max),
        "sarmap.classes": args.classes,
    })
    if class_map:
        metadata["sarmap.class_map"] = json.dumps(class_map)
    write_safetensors(args.output, state_dict_to_numpy(state), metadata)


if __name__ == "__main__":
    main(sys.argv[1:])
