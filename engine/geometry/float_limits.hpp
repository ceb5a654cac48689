// How far float geometry (Embree's) can be trusted against exact double
// geometry: the largest coordinate a scene or a query accepts, and the band
// around a surface within which the two may legitimately disagree.
#pragma once

namespace sarmap::geometry {

// Coordinates beyond +-100 km are refused with an error: float spacing there
// is about 8 mm, and such a value is a unit or parsing mistake, not an arena.
inline constexpr double kMaxSceneCoordinate = 1e5;

// Within +-100 m of the origin (any arena), a TriangleScene's answer for a
// segment equals the exact double-precision reference (segment_box.hpp)
// unless the segment comes within this distance of a surface without
// crossing it, crosses by less than it, or has an endpoint this close to a
// surface. Float rounding of vertices and endpoints (under 1e-5 m at 100 m)
// plus Embree's tnear/tfar rule ("no guarantee exactly at the ends") fit in it
// with a tenfold margin. Farther out the band grows with |coordinate| (about
// 1e-6 of it).
inline constexpr double kSurfaceTolerance = 1e-4;

}  // namespace sarmap::geometry
