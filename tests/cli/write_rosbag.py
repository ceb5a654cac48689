#!/usr/bin/python3
"""Writes a ROS 1 bag from frames the rosbag input test prepared, for sarmap's
bag reader to be checked against the same frames read as a sequence folder.

Needs Debian's python3-rosbag (the message classes are generated here from
their definitions with genpy, so no ROS message package is needed).

FRAMES holds frames.txt ("stamp tx ty tz qx qy qz qw" per frame: the sensor
frame's pose in the world) and frame_N.bin (per point: float32 x, y, z in the
sensor frame and uint8 label). Exit code 77: python3-rosbag is missing.
"""
import argparse
import math
import os
import struct
import sys

try:
    import genpy
    import genpy.dynamic
    import rosbag
except ImportError as e:  # the test treats 77 as "skipped"
    print(f"python3-rosbag is missing: {e}", file=sys.stderr)
    sys.exit(77)

HEADER = """uint32 seq
time stamp
string frame_id"""
POINT = """float64 x
float64 y
float64 z"""
QUATERNION = """float64 x
float64 y
float64 z
float64 w"""
POSE = """geometry_msgs/Point position
geometry_msgs/Quaternion orientation"""
SEP = "\n" + "=" * 80 + "\nMSG: "

DEFINITIONS = {
    "sensor_msgs/PointCloud2": """std_msgs/Header header
uint32 height
uint32 width
sensor_msgs/PointField[] fields
bool is_bigendian
uint32 point_step
uint32 row_step
uint8[] data
bool is_dense""" + SEP + "std_msgs/Header\n" + HEADER + SEP + """sensor_msgs/PointField
uint8 INT8=1
uint8 UINT8=2
uint8 INT16=3
uint8 UINT16=4
uint8 INT32=5
uint8 UINT32=6
uint8 FLOAT32=7
uint8 FLOAT64=8
string name
uint32 offset
uint8 datatype
uint32 count""",
    "nav_msgs/Odometry": """std_msgs/Header header
string child_frame_id
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist""" + SEP + "std_msgs/Header\n" + HEADER + SEP + """geometry_msgs/PoseWithCovariance
geometry_msgs/Pose pose
float64[36] covariance""" + SEP + "geometry_msgs/Pose\n" + POSE + SEP + "geometry_msgs/Point\n" + POINT + SEP +
    "geometry_msgs/Quaternion\n" + QUATERNION + SEP + """geometry_msgs/TwistWithCovariance
geometry_msgs/Twist twist
float64[36] covariance""" + SEP + """geometry_msgs/Twist
geometry_msgs/Vector3 linear
geometry_msgs/Vector3 angular""" + SEP + "geometry_msgs/Vector3\n" + POINT,
    "geometry_msgs/PoseStamped": """std_msgs/Header header
geometry_msgs/Pose pose""" + SEP + "std_msgs/Header\n" + HEADER + SEP + "geometry_msgs/Pose\n" + POSE + SEP +
    "geometry_msgs/Point\n" + POINT + SEP + "geometry_msgs/Quaternion\n" + QUATERNION,
    "tf2_msgs/TFMessage": """geometry_msgs/TransformStamped[] transforms""" + SEP + """geometry_msgs/TransformStamped
std_msgs/Header header
string child_frame_id
geometry_msgs/Transform transform""" + SEP + "std_msgs/Header\n" + HEADER + SEP + """geometry_msgs/Transform
geometry_msgs/Vector3 translation
geometry_msgs/Quaternion rotation""" + SEP + "geometry_msgs/Vector3\n" + POINT + SEP + "geometry_msgs/Quaternion\n" +
    QUATERNION,
}


def message_class(name):
    return genpy.dynamic.generate_dynamic(name, DEFINITIONS[name])[name]


PointCloud2 = message_class("sensor_msgs/PointCloud2")
Odometry = message_class("nav_msgs/Odometry")
PoseStamped = message_class("geometry_msgs/PoseStamped")
TFMessage = message_class("tf2_msgs/TFMessage")
PointField = genpy.dynamic.generate_dynamic("sensor_msgs/PointCloud2",
                                            DEFINITIONS["sensor_msgs/PointCloud2"])["sensor_msgs/PointField"]
TransformStamped = genpy.dynamic.generate_dynamic(
    "tf2_msgs/TFMessage", DEFINITIONS["tf2_msgs/TFMessage"])["geometry_msgs/TransformStamped"]


def read_frames(folder):
    frames = []
    with open(os.path.join(folder, "frames.txt")) as f:
        for i, line in enumerate(f):
            v = [float(t) for t in line.split()]
            with open(os.path.join(folder, f"frame_{i}.bin"), "rb") as b:
                data = b.read()
            points = [struct.unpack_from("<fffB", data, k) for k in range(0, len(data), 13)]
            frames.append({"stamp": v[0], "t": v[1:4], "q": v[4:8], "points": points})
    return frames


def cloud(frame, xyz64, seq):
    """Two rows with padding after each point and each row, and a NaN point
    at the end of each row: the reader must honour point_step and row_step
    and drop what is not finite."""
    fmt, size, datatype = ("<ddd", 8, 8) if xyz64 else ("<fff", 4, 7)
    point_step = 3 * size + 4  # x y z, label, 3 bytes of padding
    points = list(frame["points"])
    half = (len(points) + 1) // 2
    rows = [points[:half], points[half:]]
    width = half + 1
    row_step = width * point_step + 8
    data = bytearray()
    for row in rows:
        start = len(data)
        for x, y, z, label in row + [(math.nan, 0.0, 0.0, 0)] * (width - len(row)):
            data += struct.pack(fmt, x, y, z) + struct.pack("<B", label) + b"\0\0\0"
        data += b"\0" * (row_step - (len(data) - start))
    m = PointCloud2()
    m.header.seq = seq
    m.header.stamp = genpy.Time.from_sec(frame["stamp"])
    m.header.frame_id = "sensor"
    m.height, m.width = 2, width
    m.fields = [PointField(name=n, offset=o, datatype=datatype, count=1) for n, o in (("x", 0), ("y", size), ("z", 2 * size))]
    m.fields.append(PointField(name="label", offset=3 * size, datatype=2, count=1))
    m.is_bigendian = False
    m.point_step, m.row_step = point_step, row_step
    m.data = bytes(data)
    m.is_dense = False
    return m


def set_pose(pose, t, q):
    pose.position.x, pose.position.y, pose.position.z = t
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q


def transform(parent, child, stamp, t, q):
    ts = TransformStamped()
    ts.header.stamp = genpy.Time.from_sec(stamp)
    ts.header.frame_id, ts.child_frame_id = parent, child
    ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = t
    r = ts.transform.rotation
    r.x, r.y, r.z, r.w = q
    return ts


def pose_messages(kind, stamp, t, q):
    """(topic, message) pairs placing the sensor at `stamp`."""
    if kind == "odometry":
        m = Odometry()
        m.header.stamp = genpy.Time.from_sec(stamp)
        m.header.frame_id, m.child_frame_id = "map", "sensor"
        set_pose(m.pose.pose, t, q)
        return [("/odom", m)]
    if kind == "pose_stamped":
        m = PoseStamped()
        m.header.stamp = genpy.Time.from_sec(stamp)
        m.header.frame_id = "map"
        set_pose(m.pose, t, q)
        return [("/pose", m)]
    m = TFMessage()
    m.transforms = [transform("map", "sensor", stamp, t, q)]
    return [("/tf", m)]


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("frames")
    parser.add_argument("out")
    parser.add_argument("--pose", choices=["odometry", "pose_stamped", "tf", "none"], default="odometry")
    parser.add_argument("--xyz64", action="store_true", help="x, y, z as float64")
    parser.add_argument("--compression", choices=["none", "bz2", "lz4"], default="none")
    parser.add_argument("--second-cloud-topic", action="store_true", help="one more PointCloud2 topic")
    parser.add_argument("--drop-pose", type=int, default=-1, help="no pose near this frame")
    parser.add_argument("--empty", action="store_true", help="a bag with no messages")
    a = parser.parse_args()

    with rosbag.Bag(a.out, "w", compression=a.compression) as bag:
        if a.empty:
            return
        frames = read_frames(a.frames)
        if a.pose == "tf":
            # A static edge elsewhere in the tree, which the lookup must not need.
            static = TFMessage()
            static.transforms = [transform("map", "charger", 0.0, (1.0, 2.0, 0.0), (0.0, 0.0, 0.0, 1.0))]
            bag.write("/tf_static", static, genpy.Time.from_sec(frames[0]["stamp"]))
        for i, frame in enumerate(frames):
            stamp = genpy.Time.from_sec(frame["stamp"])
            bag.write("/points", cloud(frame, a.xyz64, i), stamp)
            if a.second_cloud_topic:
                bag.write("/points_raw", cloud(frame, a.xyz64, i), stamp)
            if a.pose == "none" or i == a.drop_pose:
                continue
            # The right pose 1 ms after the cloud, and a wrong one 0.4 s before
            # it: the nearest in time must win.
            for topic, m in pose_messages(a.pose, frame["stamp"] + 0.001, frame["t"], frame["q"]):
                bag.write(topic, m, genpy.Time.from_sec(frame["stamp"] + 0.001))
            for topic, m in pose_messages(a.pose, frame["stamp"] - 0.4, (9.0, 9.0, 9.0), (0.0, 0.0, 0.0, 1.0)):
                bag.write(topic, m, genpy.Time.from_sec(frame["stamp"] - 0.4))


if __name__ == "__main__":
    main()
