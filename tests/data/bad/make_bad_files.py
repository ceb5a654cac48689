#!/usr/bin/env python3
"""Writes the corpus of broken PLY and PCD files in tests/data/bad: one defect
per file, each named for its defect. tests/io/*_bad_input_test.cpp expects a
sarmap::Error naming the file, the line or byte offset, and what was wrong.
Run from anywhere: python3 tests/data/bad/make_bad_files.py"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def ply_header(fmt, count, props, extra=""):
    lines = ["ply", "format %s 1.0" % fmt, "element vertex %d" % count]
    lines += ["property %s %s" % (t, n) for t, n in props]
    return "\n".join(lines) + "\n" + extra + "end_header\n"


XYZ = [("float", "x"), ("float", "y"), ("float", "z")]
ASCII_ROWS = "1.000 2.000 3.000\n4.000 5.000 6.000\n7.000 8.000 9.000\n"


def xyz_records(n):
    return b"".join(struct.pack("<3f", i, i + 1, i + 2) for i in range(n))


def pcd_header(fields, sizes, types, counts, width, points, data, height=1):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\nCOUNT %s\n"
            "WIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA %s\n"
            % (fields, sizes, types, counts, width, height, points, data))


def pcd_xyz(points, data, width=None):
    return pcd_header("x y z", "4 4 4", "F F F", "1 1 1", points if width is None else width, points, data)


def ply_files():
    # Binary data stops in the middle of vertex 5 of 10.
    write("ply_truncated_binary.ply", ply_header("binary_little_endian", 10, XYZ).encode() + xyz_records(5) + b"\0\0")
    # The header says 5 vertices, the data has 3 (long enough rows that the
    # size check passes and the line count is what fails).
    write("ply_count_too_large_ascii.ply", ply_header("ascii", 5, XYZ) + ASCII_ROWS + "\n")
    # The header says 2 vertices, the data has 3.
    write("ply_count_too_small_ascii.ply", ply_header("ascii", 2, XYZ) + ASCII_ROWS)
    # Line 9 holds "abc" where y should be.
    write("ply_non_numeric.ply", ply_header("ascii", 3, XYZ) + "1 2 3\n4 abc 6\n7 8 9\n")
    # Line 9 lacks z.
    write("ply_too_few_values.ply", ply_header("ascii", 2, XYZ) + "1.000 2.000 3.000\n4.000 5.000\n")
    write("ply_missing_z.ply", ply_header("ascii", 1, XYZ[:2] + [("float", "intensity")]) + "1 2 3\n")
    write("ply_bad_type.ply", ply_header("ascii", 1, [("float", "x"), ("float128", "y"), ("float", "z")]) + "1 2 3\n")
    write("ply_color_not_uchar.ply", ply_header("ascii", 1, XYZ + [("float", "red")]) + "1 2 3 0.5\n")
    # An absurd count in a file of about 200 bytes.
    write("ply_huge_count.ply", ply_header("binary_little_endian", 999999999999, XYZ).encode() + xyz_records(8))
    write("ply_big_endian.ply", ply_header("binary_big_endian", 1, XYZ).encode() + struct.pack(">3f", 1, 2, 3))
    write("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n")
    write("ply_not_ply.ply", "solid cube\nfacet normal 0 0 1\n")
    # int label 300 in the second vertex (byte offset 134 + 16 + 12 = 162).
    header = ply_header("binary_little_endian", 2, XYZ + [("int", "label")]).encode()
    write("ply_label_out_of_range.ply",
          header + struct.pack("<3fi", 1, 2, 3, 1) + struct.pack("<3fi", 4, 5, 6, 300))
    # 2 vertices declared, 3 present, nothing after the vertex element.
    write("ply_binary_trailing_bytes.ply", ply_header("binary_little_endian", 2, XYZ).encode() + xyz_records(3))
    # A list in the vertex records claims 200 items; the file ends first.
    header = ply_header("binary_little_endian", 1, XYZ + [("list uchar float", "extra")]).encode()
    write("ply_truncated_list.ply", header + struct.pack("<3fB", 1, 2, 3, 200) + struct.pack("<2f", 0, 0))
    write("ply_no_vertex_element.ply",
          "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n")
    write("ply_bad_count.ply", "ply\nformat ascii 1.0\nelement vertex -4\nproperty float x\nend_header\n")


def pcd_files():
    write("pcd_truncated_binary.pcd", pcd_xyz(10, "binary").encode() + xyz_records(6) + b"\0")
    write("pcd_points_mismatch.pcd", pcd_xyz(6, "ascii", width=5) + "1 2 3\n" * 6)
    # Line 13 (the second data line) has "x" where z should be.
    write("pcd_non_numeric.pcd", pcd_xyz(3, "ascii") + "1 2 3\n4 5 x\n7 8 9\n")
    write("pcd_missing_x.pcd", pcd_header("y z", "4 4", "F F", "1 1", 1, 1, "ascii") + "1 2\n")
    write("pcd_bad_type_size.pcd", pcd_header("x y z", "4 2 4", "F F F", "1 1 1", 1, 1, "ascii") + "1 2 3\n")
    write("pcd_unknown_type.pcd", pcd_header("x y z", "4 4 4", "F D F", "1 1 1", 1, 1, "ascii") + "1 2 3\n")
    write("pcd_huge_points.pcd", pcd_xyz(999999999999, "binary").encode() + xyz_records(8))
    write("pcd_huge_points_ascii.pcd", pcd_xyz(999999999999, "ascii") + "1 2 3\n")
    write("pcd_size_count_mismatch.pcd", pcd_header("x y z", "4 4", "F F F", "1 1 1", 1, 1, "ascii") + "1 2 3\n")
    write("pcd_no_data_line.pcd", pcd_xyz(1, "ascii").replace("DATA ascii\n", ""))
    write("pcd_count_too_large_ascii.pcd", pcd_xyz(5, "ascii") + ASCII_ROWS)
    write("pcd_count_too_small_ascii.pcd", pcd_xyz(2, "ascii") + ASCII_ROWS)
    write("pcd_label_count.pcd",
          pcd_header("x y z label", "4 4 4 4", "F F F U", "1 1 1 2", 1, 1, "ascii") + "1 2 3 4 5\n")
    write("pcd_bad_data_kind.pcd", pcd_xyz(1, "binary_lzma") + "1 2 3\n")
    # 2 points declared, 3 present: the trailing bytes are a point, not zero padding.
    write("pcd_binary_trailing_bytes.pcd", pcd_xyz(2, "binary").encode() + xyz_records(3))
    # binary_compressed: 2 points of 12 bytes, so 24 bytes uncompressed.
    raw = struct.pack("<2f", 1, 4) + struct.pack("<2f", 2, 5) + struct.pack("<2f", 3, 6)
    literal = bytes([len(raw) - 1]) + raw
    head = pcd_xyz(2, "binary_compressed").encode()
    # A back-reference 200 bytes back at the very start of the stream.
    bad_ref = bytes([0x20 | 0, 199]) + literal
    write("pcd_compressed_bad_reference.pcd", head + struct.pack("<II", len(bad_ref), len(raw)) + bad_ref)
    write("pcd_compressed_size_too_large.pcd", head + struct.pack("<II", 5000, len(raw)) + literal)
    write("pcd_compressed_wrong_uncompressed_size.pcd", head + struct.pack("<II", len(literal), 36) + literal)
    # The literal run is cut off: 25 bytes announced, 10 present.
    write("pcd_compressed_truncated_stream.pcd", head + struct.pack("<II", 11, len(raw)) + literal[:11])
    write("pcd_compressed_missing_sizes.pcd", head + b"\x05\x00")


if __name__ == "__main__":
    ply_files()
    pcd_files()
