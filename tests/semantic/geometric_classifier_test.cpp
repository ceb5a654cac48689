// The geometric baseline on an exact synthetic scene (floor, wall, a flat ramp
// box, a 15-degree inclined ramp): PCA normals against the true planes, the
// classes away from edges against the truth, the same answer wherever the
// scene sits, and the errors and limits.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/geometric/geometric_classifier.hpp"
#include "engine/semantic/surface_normals.hpp"

namespace sarmap {
namespace {

constexpr double kIncline = 15.0 * std::numbers::pi / 180.0;

// A scene sampled on a 2 cm grid with a little noise; gt_label holds each
// point's class and `interior` says whether it lies 10 cm or more from any
// edge, where the class is unambiguous from the geometry.
struct Scene {
  PointBuffer points;
  std::vector<bool> interior;
};

Scene make_scene(double shift_x = 0.0, double shift_z = 0.0) {
  Scene s;
  s.points.enable_gt_labels();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.002);
  const auto add = [&](double x, double y, double z, ClassId c, bool interior) {
    s.points.push_back(static_cast<float>(x + shift_x + noise(rng)), static_cast<float>(y + noise(rng)),
                       static_cast<float>(z + shift_z + noise(rng)));
    s.points.gt_labels().back() = static_cast<std::uint8_t>(c);
    s.interior.push_back(interior);
  };
  const double step = 0.02;
  const auto inside = [](double v, double lo, double hi, double margin) { return v >= lo + margin && v <= hi - margin; };
  // Floor 0..5 x 0..4, except under the box (1..2 x 1..2) and the ramp (3..4.2 x 1..2).
  for (double x = 0.01; x < 5.0; x += step) {
    for (double y = 0.01; y < 4.0; y += step) {
      const bool under_box = inside(x, 1, 2, 0) && inside(y, 1, 2, 0);
      const bool under_ramp = inside(x, 3, 4.2, 0) && inside(y, 1, 2, 0);
      if (under_box || under_ramp) continue;
      const bool near_feature = (inside(x, 0.9, 2.1, 0) && inside(y, 0.9, 2.1, 0)) ||
                                (inside(x, 2.9, 4.3, 0) && inside(y, 0.9, 2.1, 0)) || x > 4.9;
      add(x, y, 0.0, ClassId::Terrain, !near_feature);
    }
  }
  // Wall at x = 5, 1.5 m tall.
  for (double y = 0.01; y < 4.0; y += step)
    for (double z = 0.01; z < 1.5; z += step) add(5.0, y, z, ClassId::Wall, z > 0.1 && z < 1.4);
  // Flat ramp: a 0.3 m box, top and the two sides facing -x and -y.
  for (double x = 1.01; x < 2.0; x += step)
    for (double y = 1.01; y < 2.0; y += step)
      add(x, y, 0.3, ClassId::FlatRamp, inside(x, 1, 2, 0.1) && inside(y, 1, 2, 0.1));
  for (double t = 1.01; t < 2.0; t += step) {
    for (double z = 0.01; z < 0.3; z += step) {
      add(1.0, t, z, ClassId::FlatRamp, false);
      add(t, 1.0, z, ClassId::FlatRamp, false);
    }
  }
  // Inclined ramp rising along +x from the floor at x = 3 to x = 4.2.
  for (double x = 3.01; x < 4.2; x += step)
    for (double y = 1.01; y < 2.0; y += step)
      add(x, y, (x - 3.0) * std::tan(kIncline), ClassId::InclinedRamp, inside(x, 3, 4.2, 0.1) && inside(y, 1, 2, 0.1));
  return s;
}

double interior_accuracy(const Scene& s, ClassId c) {
  std::size_t right = 0, total = 0;
  for (std::size_t p = 0; p < s.points.size(); ++p) {
    if (!s.interior[p] || s.points.gt_labels()[p] != static_cast<std::uint8_t>(c)) continue;
    ++total;
    right += s.points.labels()[p] == s.points.gt_labels()[p];
  }
  EXPECT_GT(total, 100u) << "class " << static_cast<int>(c);
  return total ? static_cast<double>(right) / static_cast<double>(total) : 0.0;
}

TEST(SurfaceNormals, MatchTheTruePlaneAndAreFlatThere) {
  const Scene s = make_scene();
  const SurfaceNormals normals = estimate_surface_normals(s.points, {});
  const double ramp_nz = std::cos(kIncline);
  for (std::size_t p = 0; p < s.points.size(); ++p) {
    if (!s.interior[p]) continue;
    ASSERT_TRUE(normals.valid[p]) << p;
    const auto c = static_cast<ClassId>(s.points.gt_labels()[p]);
    const double expected_nz = c == ClassId::Wall ? 0.0 : c == ClassId::InclinedRamp ? ramp_nz : 1.0;
    // Within 2 degrees of the true plane (2 mm noise on a 15 cm patch); unit length; flat.
    EXPECT_NEAR(normals.nz[p], expected_nz, 0.035) << p;
    EXPECT_NEAR(std::hypot(normals.nx[p], normals.ny[p], normals.nz[p]), 1.0, 1e-5);
    EXPECT_GE(normals.nz[p], 0.0f);
    EXPECT_LT(normals.curvature[p], 0.01f) << p;
  }
}

TEST(SurfaceNormals, SparsePointsHaveNoneAndBadInputIsRefused) {
  PointBuffer sparse;
  for (int i = 0; i < 4; ++i) sparse.push_back(static_cast<float>(i), 0, 0);  // one point per neighbourhood
  const SurfaceNormals normals = estimate_surface_normals(sparse, {});
  for (std::size_t p = 0; p < sparse.size(); ++p) EXPECT_FALSE(normals.valid[p]);
  EXPECT_TRUE(estimate_surface_normals(PointBuffer{}, {}).valid.empty());

  PointBuffer with_nan = sparse;
  with_nan.push_back(std::numeric_limits<float>::quiet_NaN(), 0, 0);
  EXPECT_THROW(estimate_surface_normals(with_nan, {}), Error);
  SurfaceNormalSettings tiny;
  tiny.cell = 0.001;
  EXPECT_THROW(estimate_surface_normals(sparse, tiny), Error);
}

TEST(GeometricClassifier, LabelsEachSurfaceAwayFromEdges) {
  Scene s = make_scene();
  const GeometricClassifyStats stats = GeometricClassifier{}.classify(s.points);
  EXPECT_EQ(stats.without_normal, 0u);
  EXPECT_GT(interior_accuracy(s, ClassId::Terrain), 0.99);
  EXPECT_GT(interior_accuracy(s, ClassId::Wall), 0.99);
  EXPECT_GT(interior_accuracy(s, ClassId::FlatRamp), 0.99);
  EXPECT_GT(interior_accuracy(s, ClassId::InclinedRamp), 0.99);
  // The box's short sides take the class of the top they hold up.
  std::size_t side_points = 0, side_right = 0;
  for (std::size_t p = 0; p < s.points.size(); ++p) {
    const bool side = s.points.gt_labels()[p] == static_cast<std::uint8_t>(ClassId::FlatRamp) &&
                      s.points.z()[p] < 0.25f && s.points.z()[p] > 0.1f;
    side_points += side;
    side_right += side && s.points.labels()[p] == static_cast<std::uint8_t>(ClassId::FlatRamp);
  }
  ASSERT_GT(side_points, 100u);
  EXPECT_GT(static_cast<double>(side_right) / static_cast<double>(side_points), 0.9);
}

TEST(GeometricClassifier, GivesTheSameClassesWhereverTheSceneSits) {
  Scene here = make_scene();
  Scene there = make_scene(1000.0, 3.0);  // far from the origin, on a raised floor
  GeometricClassifier{}.classify(here.points);
  GeometricClassifier{}.classify(there.points);
  std::size_t differ = 0;
  for (std::size_t p = 0; p < here.points.size(); ++p) differ += here.points.labels()[p] != there.points.labels()[p];
  // float coordinates 1 km out move a few points across cell borders.
  EXPECT_LT(differ, here.points.size() / 200);
}

TEST(GeometricClassifier, PointsBeyondTheMapLimitAreUnknown) {
  Scene s = make_scene();
  s.points.push_back(2.0e4f, 0.0f, 0.0f);
  GeometricClassifier{}.classify(s.points);
  EXPECT_EQ(s.points.labels().back(), static_cast<std::uint8_t>(ClassId::Unknown));
  EXPECT_GT(interior_accuracy(s, ClassId::Terrain), 0.99);
}

TEST(GeometricClassifier, RefusesInconsistentSettings) {
  GeometricClassifierSettings angles;
  angles.inclined_max_deg = 5.0;  // below horizontal_max_deg
  EXPECT_THROW(GeometricClassifier{angles}, Error);
  GeometricClassifierSettings heights;
  heights.flat_ramp_max_height = 1.0;  // above wall_min_height
  EXPECT_THROW(GeometricClassifier{heights}, Error);
}

}  // namespace
}  // namespace sarmap
