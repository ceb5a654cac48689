"""One frame of a sequence as open_sequence() yields it: it unpacks as the
(points, pose, origin) triple and carries the rest as attributes."""


class Scan(tuple):
    """(points, pose, origin): points, a PointCloud in the world frame with the
    frame's own fields (labels, colours, ...); pose, the (4, 4) float64
    sensor-to-world matrix; origin, the (3,) float64 ray origin. Also index
    (frame number), source (the frame's file), timestamp (seconds) and
    dropped_non_finite (points with a NaN or infinite coordinate dropped on
    reading)."""

    def __new__(cls, points, pose, origin, index, source, timestamp, dropped_non_finite):
        scan = super().__new__(cls, (points, pose, origin))
        scan.index = index
        scan.source = source
        scan.timestamp = timestamp
        scan.dropped_non_finite = dropped_non_finite
        return scan

    points = property(lambda self: self[0])
    pose = property(lambda self: self[1])
    origin = property(lambda self: self[2])

    def __repr__(self):
        return f"Scan(index={self.index}, points={len(self[0])}, source={self.source!r})"
