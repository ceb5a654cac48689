#!/usr/bin/env python3
"""Writes the fuzz seed corpora, fuzz/corpus/<target>/, from the repository's
test data and a few small files made here the way the tests make them
(docs/reliability.md, "Fuzzing"). Run from anywhere; rerun after changing a
format. Every seed stays a few KB so the fuzzers mutate quickly."""
import json
import shutil
import struct
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT / "fuzz" / "corpus"
SEPARATOR = b"\n=====\n"  # fuzz_support.hpp's kPartSeparator


def put(target, name, data):
    folder = CORPUS / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data)


def copy(target, *paths):
    for p in paths:
        put(target, Path(p).name, (ROOT / p).read_bytes())


# --- PNG -------------------------------------------------------------------
def png(width, height, values, bit_depth=16, color_type=0, interlace=0):
    channels = {0: 1, 2: 3}[color_type]
    sample = 2 if bit_depth == 16 else 1
    raw = b""
    for y in range(height):
        row = b"".join(
            (struct.pack(">H", values[(y * width + x) % len(values)]) if sample == 2
             else bytes([values[(y * width + x) % len(values)] & 0xFF])) * channels
            for x in range(width))
        raw += b"\x00" + row

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, interlace)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) +
            chunk(b"IEND", b""))


# --- safetensors -----------------------------------------------------------
def safetensors(tensors, metadata=None):
    """tensors: list of (name, dtype, shape, bytes)."""
    header, data = {}, b""
    for name, dtype, shape, payload in tensors:
        header[name] = {"dtype": dtype, "shape": shape, "data_offsets": [len(data), len(data) + len(payload)]}
        data += payload
    if metadata:
        header["__metadata__"] = metadata
    text = json.dumps(header, separators=(",", ":")).encode()
    return struct.pack("<Q", len(text)) + text + data


def floats(count, seed):
    # Small non-zero weights of both signs (a model of all-zero layers is refused).
    return struct.pack("<%df" % count, *[((i * 37 + seed * 11) % 19 - 9) / 10.0 or 0.05 for i in range(count)])


def tiny_dgcnn(width=4, channels=3, classes=4, prefix="", bn_duplicates=False):
    """A DGCNN_semseg with every layer `width` wide: the reference's tensor names."""
    ins = [2 * channels, width, 2 * width, width, 2 * width, 3 * width, 4 * width, width, width]
    tensors = []
    for i, n_in in enumerate(ins, start=1):
        out = classes if i == 9 else width
        if i == 9:
            tensors.append((f"{prefix}conv9.weight", "F32", [out, n_in, 1], floats(out * n_in, i)))
            continue
        shape = [out, n_in, 1, 1] if i <= 5 else [out, n_in, 1]
        tensors.append((f"{prefix}conv{i}.0.weight", "F32", shape, floats(out * n_in, i)))
        bn = [("weight", floats(out, i + 1)), ("bias", floats(out, i + 2)), ("running_mean", floats(out, i + 3)),
              ("running_var", struct.pack("<%df" % out, *[1.0 + 0.1 * k for k in range(out)]))]
        for key, payload in bn:
            tensors.append((f"{prefix}conv{i}.1.{key}", "F32", [out], payload))
            if bn_duplicates:
                tensors.append((f"{prefix}bn{i}.{key}", "F32", [out], payload))
    return tensors


MODEL_METADATA = {"sarmap.k": "5", "sarmap.points_per_block": "64", "sarmap.block_size": "1.0",
                  "sarmap.normalisation": "cell_xy_fixed_z", "sarmap.z_min": "-0.5", "sarmap.z_max": "2.5",
                  "sarmap.classes": "terrain,wall,inclined_ramp,flat_ramp"}


# --- npy -------------------------------------------------------------------
def npy(shape, values, version=(1, 0), descr="<f4", fortran=False):
    dims = ", ".join(str(d) for d in shape) + ("," if len(shape) == 1 else "")
    text = "{'descr': '%s', 'fortran_order': %s, 'shape': (%s), }" % (descr, fortran, dims)
    size_bytes = 2 if version[0] == 1 else 4
    pad = (-(10 + (size_bytes - 2) + len(text) + 1)) % 64
    text = (text + " " * pad + "\n").encode()
    head = b"\x93NUMPY" + bytes(version) + struct.pack("<H" if size_bytes == 2 else "<I", len(text))
    return head + text + struct.pack("<%df" % len(values), *values)


# --- map.sarmap (without its trailing CRC: map_file_fuzz.cpp appends it) ----
def sarmap_map(blocks, version=3):
    """blocks: [(key, voxels)], voxels(v) -> (log_odds, evidence[6]); version 3 takes a byte per
    value (log-odds -128 unknown), versions 1 and 2 two (-32768 unknown)."""
    value = "b" if version >= 3 else "h"
    head = b"SARMAPVX" + struct.pack("<I", version) + struct.pack("<d", 0.05) + bytes([1, version])
    head += struct.pack("<H", 7 if version >= 3 else 14)
    head += struct.pack("<8d", 0.7, 0.4, 0.12, 0.97, 0.5, 0.9, 20.0, 0.5)
    head += struct.pack("<Q", len(blocks))
    for key, voxels in blocks:
        values = [voxels(v) for v in range(512)]
        head += struct.pack("<3i", *key)
        if version == 1:
            for log_odds, evidence in values:
                head += struct.pack("<h6h", log_odds, *evidence)
            continue
        log_odds = [lo for lo, _ in values]
        if len(set(log_odds)) == 1:
            head += bytes([0]) + struct.pack("<" + value, log_odds[0])
        else:
            head += bytes([1]) + struct.pack("<512" + value, *log_odds)
        mask = [0] * 8
        for v, (_, evidence) in enumerate(values):
            if any(evidence):
                mask[v // 64] |= 1 << (v % 64)
        head += struct.pack("<8Q", *mask)
        for _, evidence in values:
            if any(evidence):
                head += struct.pack("<6" + value, *evidence)
    return head


def main():
    if CORPUS.exists():
        shutil.rmtree(CORPUS)

    copy("ply", "tests/data/clouds/meshlab_faces_ascii.ply", "tests/data/clouds/mixed_types_ascii.ply",
         "tests/data/clouds/mixed_types_binary.ply", "tests/data/sequences/tiny/frame_000000.ply",
         "tests/data/bad/ply_truncated_list.ply", "tests/data/bad/ply_binary_trailing_bytes.ply")
    copy("pcd", "tests/data/clouds/normals_compressed.pcd", "tests/data/clouds/pcl_fpfh_count_ascii.pcd",
         "tests/data/clouds/pcl_xyzrgb_ascii.pcd", "tests/data/clouds/pcl_xyzrgbl_binary.pcd",
         "tests/data/bad/pcd_compressed_bad_reference.pcd", "tests/data/bad/pcd_truncated_binary.pcd")

    put("npy", "block_4x3.npy", npy((4, 3), [0.5 * i for i in range(12)]))
    put("npy", "cube_2x2x2.npy", npy((2, 2, 2), [float(i) for i in range(8)]))
    put("npy", "empty.npy", npy((0,), []))
    put("npy", "version2.npy", npy((3,), [1.0, 2.0, 3.0], version=(2, 0)))

    put("safetensors", "tiny_model.safetensors", safetensors(tiny_dgcnn(), MODEL_METADATA))
    put("safetensors", "mixed_dtypes.safetensors", safetensors([
        ("a", "F32", [2, 3], floats(6, 1)), ("b", "F64", [2], struct.pack("<2d", 1.5, -2.0)),
        ("c", "I64", [], struct.pack("<q", 7)), ("d", "F32", [0, 4], b"")], {"note": "seed"}))

    put("dgcnn_model", "tiny_model.safetensors", safetensors(tiny_dgcnn(), MODEL_METADATA))
    put("dgcnn_model", "tiny_model_c6_no_metadata.safetensors", safetensors(tiny_dgcnn(channels=6)))
    put("dgcnn_model", "tiny_model_module_prefix.safetensors",
        safetensors(tiny_dgcnn(width=3, classes=5, prefix="module.", bn_duplicates=True),
                    dict(MODEL_METADATA, **{"sarmap.classes": "terrain,wall,inclined_ramp,flat_ramp,other"})))
    # Another data set's class list with a map onto sarmap's (S3DIS's 13 names).
    put("dgcnn_model", "tiny_model_s3dis_class_map.safetensors",
        safetensors(tiny_dgcnn(classes=13), dict(MODEL_METADATA, **{
            "sarmap.classes": "ceiling,floor,wall,beam,column,window,door,table,chair,sofa,bookcase,board,clutter",
            "sarmap.class_map": json.dumps({"board": "wall", "door": "other"})})))

    copy("arena", "datasets/arenas/esogu-6x4.json", "datasets/arenas/building-52x15.json",
         "tests/cli/data/tiny_arena.json", "tests/cli/data/room_with_door.json")
    tiny = json.loads((ROOT / "tests/cli/data/tiny_arena.json").read_text())
    tiny["elements"].append({"type": "mesh", "path": "square.obj", "position": [1, 1, 0], "scale": [0.5, 0.5, 1]})
    tiny["elements"].append({"type": "inclined_ramp", "center": [1.0, 0.5], "size": [0.8, 0.6], "angle_deg": 15,
                             "yaw_deg": 90})
    tiny["sensor"] = {"type": "lidar", "max_range": 8.0}
    put("arena", "tiny_mesh_lidar.json", json.dumps(tiny, indent=1).encode())

    put("sarmap_sequence", "tiny_sequence.json", (ROOT / "tests/data/sequences/tiny/sequence.json").read_bytes())
    put("sarmap_sequence", "unknown_key.json",
        (ROOT / "tests/data/bad/bad_sequence_unknown_key/sequence.json").read_bytes())
    put("sarmap_sequence", "world_depth_camera.json", json.dumps({
        "version": 1, "points_frame": "world",
        "sensor": {"type": "depth_camera", "max_range": 4, "min_range": 0.2, "width": 4, "height": 3,
                   "fx": 50, "fy": 60, "cx": 1.5, "cy": 1.0},
        "frames": [{"file": "frame_000001.ply", "pose": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
                    "origin": [0, 0, 1]},
                   {"file": "frame_000000.ply", "pose": [0, 0, 1, 2, 0, 1, 0, 0, -1, 0, 0, 1, 0, 0, 0, 1],
                    "origin": [2, 0, 1]}]}, indent=1).encode())

    depth_list = b"# depth maps\n# timestamp filename\n1.000000 d.png\n1.100000 d.png\n1.500000 d.png\n"
    ground_truth = (b"# timestamp tx ty tz qx qy qz qw\n0.99 1 2 3 0 0 0 1\n"
                    b"1.095 -1 0.5 2 0 0 0.7071067811865476 0.7071067811865476\n1.21 0 0 1 0.5 0.5 0.5 0.5\n")
    put("tum", "json_intrinsics.txt", SEPARATOR.join([
        depth_list, ground_truth, b'{"fx": 50, "fy": 60, "cx": 1.5, "cy": 1.0, "width": 4, "height": 3}']))
    put("tum", "matrix_intrinsics.txt", SEPARATOR.join([
        b"1.0 d.png\n", b"1.0 0 0 0 0 0 0 1\n", b"100 0 1.5\n0 100 1\n0 0 1\n"]))

    put("seven_scenes", "matrix.txt", SEPARATOR.join([
        b"100 0 1.5\n0 100 1\n0 0 1\n", b"0 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 0 1\n"]))
    put("seven_scenes", "json_identity.txt", SEPARATOR.join([
        b'{"fx": 585, "fy": 585, "cx": 2, "cy": 1.5}', b"1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"]))

    put("depth_png", "gray16_4x3.png", png(4, 3, [5000, 0, 6000, 65535, 4000]))
    put("depth_png", "gray16_interlaced_7x5.png", png(7, 5, [1000, 2000, 0, 3000], interlace=1))
    put("depth_png", "gray8_3x2.png", png(3, 2, [10, 20, 30], bit_depth=8))
    put("depth_png", "rgb16_2x2.png", png(2, 2, [100, 200], color_type=2))

    mixed_block = ((1, -2, 0), lambda v: (
        (-128, [0] * 6) if v % 3 == 0 else (40 if v % 3 == 1 else -20, [8, -4, 0, 0, 16, 0])))
    put("map_file", "empty_map.bin", sarmap_map([]))
    put("map_file", "one_block.bin", sarmap_map([mixed_block]))
    put("map_file", "uniform_and_mixed_blocks.bin", sarmap_map([
        ((0, 0, 0), lambda v: (-60, [0] * 6)), mixed_block]))
    # Earlier versions, in their units (log-odds 1/1024 nat, evidence 1/256 nat).
    wide_block = ((1, -2, 0), lambda v: (
        (-32768, [0] * 6) if v % 3 == 0 else (40 if v % 3 == 1 else -20, [256, -128, 0, 0, 512, 0])))
    put("map_file", "version_1_one_block.bin", sarmap_map([wide_block], version=1))
    put("map_file", "version_2_one_block.bin", sarmap_map([wide_block], version=2))

    ros_messages()


# --- ROS 1 messages (ros_messages: first byte picks the type) ---------------
def ros_string(text):
    return struct.pack("<I", len(text)) + text.encode()


def ros_header(sec, frame):
    return struct.pack("<III", 0, sec, 0) + ros_string(frame)


def ros_pose(x, y, z, qx, qy, qz, qw):
    return struct.pack("<7d", x, y, z, qx, qy, qz, qw)


def point_cloud2(xyz64=False):
    kind, size = (8, 8) if xyz64 else (7, 4)
    fields = b"".join(ros_string(n) + struct.pack("<IBI", o, kind, 1) for n, o in (("x", 0), ("y", size), ("z", 2 * size)))
    fields += ros_string("label") + struct.pack("<IBI", 3 * size, 2, 1)
    point_step = 3 * size + 4
    width, height, row_step = 2, 2, 2 * point_step + 4
    data = b""
    for row in range(height):
        for col in range(width):
            v = float(row * width + col)
            data += struct.pack("<ddd" if xyz64 else "<fff", v, -v, 0.5 * v) + bytes([col, 0, 0, 0])
        data += b"\0" * 4
    return (ros_header(7, "lidar") + struct.pack("<III", height, width, 4) + fields +
            struct.pack("<BII", 0, point_step, row_step) + struct.pack("<I", len(data)) + data + b"\0")


def ros_messages():
    put("ros_messages", "cloud_float32.bin", b"\x00" + point_cloud2())
    put("ros_messages", "cloud_float64.bin", b"\x00" + point_cloud2(xyz64=True))
    put("ros_messages", "odometry.bin",
        b"\x01" + ros_header(3, "map") + ros_string("base") + ros_pose(1, 2, 3, 0, 0, 0, 1) + b"\0" * (36 * 8 * 2 + 48))
    put("ros_messages", "pose_stamped.bin", b"\x02" + ros_header(4, "map") + ros_pose(0, 0, 1, 0, 0, 1, 0))
    put("ros_messages", "tf_two_edges.bin", b"\x03" + struct.pack("<I", 2) +
        ros_header(5, "map") + ros_string("odom") + ros_pose(1, 0, 0, 0, 0, 0, 1) +
        ros_header(5, "odom") + ros_string("base") + ros_pose(0, 1, 0, 0, 0, 0.7071, 0.7071))


if __name__ == "__main__":
    main()
