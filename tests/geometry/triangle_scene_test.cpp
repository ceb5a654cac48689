// Tests of engine/geometry/triangle_scene.hpp's ray queries and mesh checks:
// the first hit and its class, the ray interval, single rays and packets
// giving the same hits, bad meshes refused with the mesh's name, scenes
// (which share one Embree device) built and traced on many threads at once,
// a scene rebuilt in place answering as one built anew, and Embree's memory
// counted while scenes live.
#include "engine/geometry/triangle_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/geometry/oriented_box.hpp"

namespace sarmap::geometry {
namespace {

ClassedMesh labelled(ClassedMesh m, ClassId label, std::string name) {
  m.label = label;
  m.name = std::move(name);
  return m;
}

// A wall across x = 2 (0.2 m thick) and a box behind it at x = 4..5.
std::vector<ClassedMesh> wall_and_box() {
  return {labelled(box_mesh(yawed_box({2, 0, 0.6}, {0.2, 4, 1.2}, 0)), ClassId::Wall, "wall"),
          labelled(box_mesh(yawed_box({4.5, 0, 0.5}, {1, 1, 1}, 0)), ClassId::Other, "box")};
}

TEST(TriangleScene, FirstHitCarriesItsMeshClass) {
  const TriangleScene scene(wall_and_box());
  ASSERT_EQ(scene.geometry_count(), 2u);
  auto hit = scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 1.9, 1e-6);
  EXPECT_EQ(hit.label, ClassId::Wall);
  // Over the wall, onto the box's top.
  hit = scene.intersect({4.5f, 0, 3}, {0, 0, -1}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 2.0, 1e-6);
  EXPECT_EQ(hit.label, ClassId::Other);
  // t is in units of the direction's length.
  hit = scene.intersect({0, 0, 0.5f}, {2, 0, 0}, 0, 100);
  EXPECT_NEAR(hit.t, 0.95, 1e-6);
}

TEST(TriangleScene, RayIntervalIsRespected) {
  const TriangleScene scene(wall_and_box());
  // Starting past the wall's near face, the next hit is its far face.
  auto hit = scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 2.0f, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 2.1, 1e-6);
  EXPECT_FALSE(scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 0, 1.8f).hit);
  EXPECT_FALSE(scene.intersect({0, 0, 0.5f}, {-1, 0, 0}, 0, 100).hit);
}

TEST(TriangleScene, RaysEmbreeWouldAbortOnAreErrors) {
  const TriangleScene scene(wall_and_box());
  const float huge = 1e19f, inf = std::numeric_limits<float>::infinity();
  EXPECT_THROW(scene.intersect({0, 0, huge}, {0, 0, -1}, 0, inf), Error);
  EXPECT_THROW(scene.intersect({0, 0, std::nanf("")}, {0, 0, -1}, 0, inf), Error);
  EXPECT_THROW(scene.intersect({0, 0, 1}, {0, std::nanf(""), -1}, 0, inf), Error);
  EXPECT_THROW(scene.intersect({0, 0, 1}, {0, 0, -1}, -1, inf), Error);
  EXPECT_THROW(scene.intersect({0, 0, 1}, {0, 0, -1}, 2, 1), Error);
  std::vector<Eigen::Vector3f> directions{{1, 0, 0}};
  std::vector<float> t(1);
  std::vector<std::uint8_t> labels(1);
  EXPECT_THROW(scene.intersect_batch({huge, 0, 0}, directions, 0, inf, t, labels), Error);
  // A far but valid origin still works.
  EXPECT_FALSE(scene.intersect({0, 0, 9e4f}, {0, 1, 0}, 0, inf).hit);
}

// embree_bytes() follows Embree's memory monitor: a scene's index and
// buffers while it lives, nothing of it after. Other tests' scenes are gone
// by now (tests of one binary run one after the other).
TEST(TriangleScene, EmbreeBytesFollowTheScenesThatLive) {
  const std::size_t before = embree_bytes();
  std::size_t one = 0;
  {
    const TriangleScene scene(wall_and_box(), BuildQuality::Low);
    one = embree_bytes();
    EXPECT_GT(one, before + 2 * 12 * 3 * sizeof(float));  // at least the boxes' vertices
    std::vector<ClassedMesh> many;
    for (int i = 0; i < 200; ++i) {
      many.push_back(labelled(box_mesh(yawed_box({0.5 * i, 0, 0.5}, {0.2, 0.2, 1}, 0)), ClassId::Other, "box"));
    }
    const TriangleScene larger(many, BuildQuality::Low);
    EXPECT_GT(embree_bytes(), one + 200 * 12 * sizeof(std::uint32_t) * 3);  // its triangles' indices at least
  }
  EXPECT_EQ(embree_bytes(), before);
}

TEST(TriangleScene, SingleRaysAndPacketsGiveTheSameHits) {
  const TriangleScene scene(wall_and_box());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  // 1000 rays: not a multiple of 16, so the last packet is partly empty.
  std::vector<Eigen::Vector3f> dirs(1000);
  // Mostly towards +x, where the wall and the box are.
  for (auto& d : dirs) d = Eigen::Vector3f(u(rng) + 1.2f, u(rng), u(rng)).normalized();
  std::vector<float> t1(dirs.size()), t16(dirs.size());
  std::vector<std::uint8_t> l1(dirs.size()), l16(dirs.size());
  const Eigen::Vector3f origin(0, 0, 0.5f);
  scene.intersect_batch(origin, dirs, 0, 100, t1, l1, RayBatchMode::Single);
  scene.intersect_batch(origin, dirs, 0, 100, t16, l16, RayBatchMode::Packet16);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    ASSERT_EQ(l1[i], l16[i]) << i;
    ASSERT_TRUE(t1[i] == t16[i]) << i << ": " << t1[i] << " vs " << t16[i];
    const auto one = scene.intersect(origin, dirs[i], 0, 100);
    ASSERT_EQ(one.hit, std::isfinite(t1[i])) << i;
    if (one.hit) {
      ++hits;
      EXPECT_EQ(one.t, t1[i]);
      EXPECT_EQ(static_cast<std::uint8_t>(one.label), l1[i]);
    }
  }
  EXPECT_GT(hits, 100u);
  EXPECT_LT(hits, 900u);
}

TEST(TriangleScene, EmptyMeshesAreSkipped) {
  std::vector<ClassedMesh> meshes = wall_and_box();
  meshes.insert(meshes.begin(), labelled(ClassedMesh{}, ClassId::Terrain, "empty"));
  const TriangleScene scene(meshes);
  EXPECT_EQ(scene.geometry_count(), 2u);
  EXPECT_EQ(scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 0, 100).label, ClassId::Wall);
}

// Two unit squares (two triangles each, known order) in the planes z = 1 and
// x = 3, after an empty mesh: which mesh and triangle a ray meets, where, and
// the normal turned towards the ray's origin whichever side it comes from.
TEST(TriangleScene, ClosestHitNamesMeshTriangleAndNormal) {
  ClassedMesh floor_square;
  floor_square.vertices = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  add_quad(floor_square, 0, 1, 2, 3);  // triangles (0, 1, 2) and (0, 2, 3)
  ClassedMesh side_square;
  side_square.vertices = {{3, 0, 0}, {3, 1, 0}, {3, 1, 1}, {3, 0, 1}};
  add_quad(side_square, 0, 1, 2, 3);
  const std::vector<ClassedMesh> meshes{labelled(ClassedMesh{}, ClassId::Terrain, "empty"),
                                        labelled(floor_square, ClassId::Terrain, "floor"),
                                        labelled(side_square, ClassId::Wall, "side")};
  const TriangleScene scene(meshes);

  // From above onto (0.8, 0.2), under triangle (0, 1, 2): x > y.
  auto hit = scene.closest_hit({0.8f, 0.2f, 3}, {0, 0, -1}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 2.0, 1e-6);
  EXPECT_EQ(hit.mesh, 1u);
  EXPECT_EQ(hit.triangle, 0u);
  EXPECT_NEAR(hit.normal.z(), 1.0, 1e-6);
  // From below onto (0.2, 0.8), triangle (0, 2, 3): the normal faces down.
  hit = scene.closest_hit({0.2f, 0.8f, -1}, {0, 0, 2}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 1.0, 1e-6);
  EXPECT_EQ(hit.mesh, 1u);
  EXPECT_EQ(hit.triangle, 1u);
  EXPECT_NEAR(hit.normal.z(), -1.0, 1e-6);
  // Sideways onto the x = 3 square, past the floor square's edge.
  hit = scene.closest_hit({5, 0.5f, 0.5f}, {-1, 0, 0}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 2.0, 1e-6);
  EXPECT_EQ(hit.mesh, 2u);
  EXPECT_NEAR(hit.normal.x(), 1.0, 1e-6);
  EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-6);
  EXPECT_FALSE(scene.closest_hit({5, 0.5f, 0.5f}, {1, 0, 0}, 0, 100).hit);
  EXPECT_THROW(scene.closest_hit({0, 0, std::nanf("")}, {0, 0, -1}, 0, 100), Error);
}

// The error's message, or "" when nothing is thrown.
std::string build_error(const ClassedMesh& bad) {
  std::vector<ClassedMesh> meshes = wall_and_box();
  meshes.push_back(bad);
  try {
    const TriangleScene scene(meshes);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidData);
    return e.what();
  }
  return "";
}

TEST(TriangleScene, BadMeshesAreRefusedByName) {
  ClassedMesh m = labelled(box_mesh(yawed_box({0, 0, 0}, {1, 1, 1}, 0)), ClassId::Other, "crate 7");
  ClassedMesh bad = m;
  bad.indices[5] = 8;
  EXPECT_EQ(build_error(bad), "crate 7: triangle index out of range");
  bad = m;
  bad.indices.pop_back();
  EXPECT_EQ(build_error(bad), "crate 7: index count is not a multiple of 3");
  bad = m;
  bad.vertices[3].y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(build_error(bad), "crate 7: vertex 3 is not finite");
  bad = m;
  bad.vertices[6].z() = std::numeric_limits<float>::infinity();
  EXPECT_EQ(build_error(bad), "crate 7: vertex 6 is not finite");
  bad = m;
  bad.vertices[0].x() = 3e5f;
  EXPECT_EQ(build_error(bad), "crate 7: vertex 0 lies beyond 100000 m");
  EXPECT_EQ(build_error(m), "");
}

// Every scene shares the process's Embree device: scenes built, traced and
// released on several threads at once, while an older scene lives on, each
// answer as the same scene gives it built alone on one thread.
TEST(TriangleScene, ScenesOnManyThreadsAtOnceAnswerAsBuiltAlone) {
  constexpr int kThreads = 4, kScenesPerThread = 25;
  // Scene s: a wall across x = 1 + s / 10; a ray from the origin along x hits it at t = 0.9 + s / 10.
  const auto scene_of = [](int s) {
    return std::vector<ClassedMesh>{labelled(box_mesh(yawed_box({1 + s / 10.0, 0, 0.5}, {0.2, 2, 1}, 0)),
                                             ClassId::Wall, "wall " + std::to_string(s))};
  };
  const auto first_hit = [](const TriangleScene& scene) { return scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 0, 100); };
  std::vector<float> alone(kThreads * kScenesPerThread);
  for (int s = 0; s < kThreads * kScenesPerThread; ++s) alone[s] = first_hit(TriangleScene(scene_of(s))).t;
  const TriangleScene older(wall_and_box());
  std::vector<float> together(alone.size(), -1);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < kScenesPerThread; ++k) {
        const int s = t * kScenesPerThread + k;
        const TriangleScene scene(scene_of(s), BuildQuality::Low);
        const TriangleScene::Hit hit = first_hit(scene);
        together[s] = hit.hit ? hit.t : -2;
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t s = 0; s < alone.size(); ++s) {
    EXPECT_NEAR(alone[s], 0.9f + static_cast<float>(s) / 10, 1e-5) << "scene " << s;
    EXPECT_EQ(together[s], alone[s]) << "scene " << s;
  }
  const TriangleScene::Hit hit = first_hit(older);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 1.9, 1e-6);
  EXPECT_EQ(hit.label, ClassId::Wall);
}

// A scene rebuilt again and again on its own storage, its meshes growing,
// shrinking, emptied, filled again, kept, moved, fewer and more, answers every
// query as a scene built anew from the same meshes: first hits (distance,
// class), closest hits (mesh, triangle) and blocked segments.
TEST(TriangleScene, RebuiltSceneAnswersAsOneBuiltAnew) {
  const ClassId classes[] = {ClassId::Wall, ClassId::Other, ClassId::Terrain, ClassId::InclinedRamp};
  for (const BuildQuality quality : {BuildQuality::Low, BuildQuality::High}) {
    std::mt19937 rng(quality == BuildQuality::Low ? 7 : 8);
    std::uniform_real_distribution<double> coord(-4, 4), size(0.1, 1.5), yaw(0, 3.14);
    std::uniform_real_distribution<float> unit(-1, 1);
    // Mesh k of a build: the last build's mesh k as it was or moved (same
    // counts, other vertices), or `boxes` random boxes (none: an empty mesh).
    const auto random_meshes = [&](int count, const std::vector<ClassedMesh>& last) {
      std::vector<ClassedMesh> meshes;
      for (int k = 0; k < count; ++k) {
        if (k < static_cast<int>(last.size()) && rng() % 2 == 0) {
          meshes.push_back(last[k]);
          if (rng() % 2 == 0) {
            for (Eigen::Vector3f& v : meshes.back().vertices) v.x() += 0.25f;
          }
          continue;
        }
        ClassedMesh m;
        const int boxes = static_cast<int>(rng() % 4) == 0 ? 0 : static_cast<int>(1 + rng() % 40);
        for (int b = 0; b < boxes; ++b) {
          append_box(m, yawed_box({coord(rng), coord(rng), coord(rng) / 4}, {size(rng), size(rng), size(rng)}, yaw(rng)));
        }
        meshes.push_back(labelled(std::move(m), classes[k % 4], "mesh " + std::to_string(k)));
      }
      return meshes;
    };
    std::vector<ClassedMesh> meshes = random_meshes(2, {});
    TriangleScene rebuilt(meshes, quality);
    const int counts[] = {3, 3, 1, 0, 2, 4, 4, 1, 3, 2, 4, 3};
    for (int round = 0; round < 12; ++round) {
      meshes = random_meshes(counts[round], meshes);
      rebuilt.rebuild(meshes);
      const TriangleScene anew(meshes, quality);
      std::size_t hits = 0;
      for (int r = 0; r < 400; ++r) {
        const Eigen::Vector3f origin(5 * unit(rng), 5 * unit(rng), unit(rng));
        const Eigen::Vector3f direction(unit(rng), unit(rng), unit(rng) / 4);
        const TriangleScene::SurfaceHit a = rebuilt.closest_hit(origin, direction, 0, 20);
        const TriangleScene::SurfaceHit b = anew.closest_hit(origin, direction, 0, 20);
        ASSERT_EQ(a.hit, b.hit) << "round " << round << ", ray " << r;
        hits += a.hit;
        if (!a.hit) continue;
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.mesh, b.mesh);
        EXPECT_EQ(a.triangle, b.triangle);
        EXPECT_EQ(rebuilt.intersect(origin, direction, 0, 20).label, meshes[a.mesh].label);
      }
      const bool any_triangle =
          std::any_of(meshes.begin(), meshes.end(), [](const ClassedMesh& m) { return !m.indices.empty(); });
      EXPECT_EQ(hits > 0, any_triangle) << "round " << round;
      std::vector<Segment> segments(300);
      for (Segment& s : segments) {
        s.p = Eigen::Vector3d(5 * unit(rng), 5 * unit(rng), unit(rng));
        s.q = Eigen::Vector3d(5 * unit(rng), 5 * unit(rng), unit(rng));
      }
      std::vector<std::uint8_t> blocked_rebuilt(segments.size()), blocked_anew(segments.size());
      rebuilt.segments_blocked(segments, blocked_rebuilt);
      anew.segments_blocked(segments, blocked_anew);
      EXPECT_EQ(blocked_rebuilt, blocked_anew) << "round " << round;
    }
  }
}

// A bad mesh is refused before the scene changes: it answers as before.
TEST(TriangleScene, RebuildRefusingABadMeshLeavesTheSceneAsItWas) {
  TriangleScene scene(wall_and_box());
  std::vector<ClassedMesh> bad = wall_and_box();
  bad[0].vertices.clear();
  bad[1].vertices.push_back({std::nanf(""), 0, 0});
  bad[1].indices.insert(bad[1].indices.end(), {0, 1, static_cast<std::uint32_t>(bad[1].vertices.size() - 1)});
  EXPECT_THROW(scene.rebuild(bad), Error);
  const TriangleScene::Hit hit = scene.intersect({0, 0, 0.5f}, {1, 0, 0}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 1.9, 1e-6);
  EXPECT_EQ(hit.label, ClassId::Wall);
}

}  // namespace
}  // namespace sarmap::geometry
