#!/bin/sh
# Writes the clouds of tests/data/clouds that real PCL made, so the PCD reader
# is tested against PCL's own writer and not only against our idea of it:
# pcl_tools_ascii.pcd (300 points x y z rgb label, written here) and PCL's
# binary and binary_compressed conversions of it. PCL 1.13's binary writer
# leaves zero bytes after the points (3906 here), which is what the binary one
# is for. Needs Debian's pcl-tools (PCL 1.13); CI only reads the files.
# Run from anywhere: sh tests/data/clouds/make_pcl_clouds.sh
set -eu
cd "$(dirname "$0")"
python3 - <<'EOF'
import math

n = 300
lines = ["# .PCD v0.7 - Point Cloud Data file format", "VERSION 0.7", "FIELDS x y z rgb label",
         "SIZE 4 4 4 4 4", "TYPE F F F U U", "COUNT 1 1 1 1 1", "WIDTH %d" % n, "HEIGHT 1",
         "VIEWPOINT 0 0 0 1 0 0 0", "POINTS %d" % n, "DATA ascii"]
for i in range(n):
    x, y, z = (i % 20) * 0.125 - 1.0, (i // 20) * 0.25, round(0.5 * math.sin(i * 0.1), 4)
    rgb = ((i * 7) % 256) << 16 | ((i * 13) % 256) << 8 | (i * 29) % 256
    lines.append("%.6g %.6g %.6g %d %d" % (x, y, z, rgb, i % 6))
with open("pcl_tools_ascii.pcd", "w") as f:
    f.write("\n".join(lines) + "\n")
EOF
pcl_convert_pcd_ascii_binary pcl_tools_ascii.pcd pcl_tools_binary.pcd 1
pcl_convert_pcd_ascii_binary pcl_tools_ascii.pcd pcl_tools_binary_compressed.pcd 2
