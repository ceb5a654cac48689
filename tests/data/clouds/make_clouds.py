#!/usr/bin/env python3
"""Writes the binary good clouds of tests/data/clouds (the ASCII ones are
written by hand). Byte layouts are spelled out with struct, independently of
sarmap's writers, so the readers are tested against a separate encoder.
Run from anywhere: python3 tests/data/clouds/make_clouds.py"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# Four points shared by several files: (x, y, z, r, g, b, label).
POINTS = [
    (0.5, -1.25, 2.0, 255, 0, 0, 1),
    (1.5, 0.0, -3.5, 0, 255, 0, 2),
    (-2.0, 4.75, 0.125, 0, 0, 255, 3),
    (10.0, 20.0, 30.0, 12, 34, 56, 4),
]


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def lzf_literals_only(data):
    """A valid LZF stream made of literal runs only (at most 32 bytes each)."""
    out = bytearray()
    for i in range(0, len(data), 32):
        chunk = data[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def ply_mixed_types_binary():
    # double x y z, int label, ushort intensity, an unknown list property and
    # an unknown uchar alpha; a "camera" element before the vertices and a face
    # element after them.
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment mixed property types\n"
        "element camera 1\nproperty float view_px\nproperty list uchar int tags\n"
        "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
        "property int label\nproperty list uchar float extra\nproperty ushort intensity\n"
        "property uchar alpha\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n")
    body = struct.pack("<fB2i", 1.5, 2, 7, 8)  # camera: view_px, tags [7, 8]
    for k, (x, y, z, r, g, b, label) in enumerate(POINTS):
        extra = [float(k)] * k  # lists of 0..3 items
        body += struct.pack("<3di", x, y, z, label)
        body += struct.pack("<B%df" % len(extra), len(extra), *extra)
        body += struct.pack("<HB", 1000 * (k + 1), 200)
    body += struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<B3i", 3, 1, 2, 3)
    write("mixed_types_binary.ply", header.encode() + body)


def pcd_xyzrgbl_binary():
    # PCL's PointXYZRGBL as pcl::io::savePCDFileBinary writes it: rgb as F 4
    # whose bits are 0x00RRGGBB, label U 4.
    header = (
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
        "FIELDS x y z rgb label\nSIZE 4 4 4 4 4\nTYPE F F F F U\nCOUNT 1 1 1 1 1\n"
        "WIDTH 4\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA binary\n")
    body = b""
    for x, y, z, r, g, b, label in POINTS:
        rgb_bits = struct.pack("<I", (r << 16) | (g << 8) | b)
        body += struct.pack("<3f", x, y, z) + rgb_bits + struct.pack("<I", label)
    write("pcl_xyzrgbl_binary.pcd", header.encode() + body)


def pcd_normals_compressed():
    # PointNormal-like with an unknown curvature and a COUNT 3 "_" padding
    # field, binary_compressed: every field's values stored one after another.
    fields = [("x", "f"), ("y", "f"), ("z", "f"), ("normal_x", "f"), ("normal_y", "f"), ("normal_z", "f"),
              ("curvature", "f"), ("intensity", "H")]
    header = (
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
        "FIELDS x y z _ normal_x normal_y normal_z curvature intensity\n"
        "SIZE 4 4 4 1 4 4 4 4 2\nTYPE F F F U F F F F U\nCOUNT 1 1 1 3 1 1 1 1 1\n"
        "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA binary_compressed\n")
    columns = {
        "x": [p[0] for p in POINTS], "y": [p[1] for p in POINTS], "z": [p[2] for p in POINTS],
        "normal_x": [0.0, 1.0, 0.0, 0.6], "normal_y": [0.0, 0.0, 1.0, 0.8], "normal_z": [1.0, 0.0, 0.0, 0.0],
        "curvature": [0.01, 0.02, 0.03, 0.04], "intensity": [10, 20, 30, 65535],
    }
    raw = b""
    for name, fmt in fields[:3]:
        raw += struct.pack("<4" + fmt, *columns[name])
    raw += bytes([0xAB] * 3 * 4)  # the padding column
    for name, fmt in fields[3:]:
        raw += struct.pack("<4" + fmt, *columns[name])
    packed = lzf_literals_only(raw)
    write("normals_compressed.pcd", header.encode() + struct.pack("<II", len(packed), len(raw)) + packed)


if __name__ == "__main__":
    ply_mixed_types_binary()
    pcd_xyzrgbl_binary()
    pcd_normals_compressed()
