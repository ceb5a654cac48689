#include "engine/segments/segment_files.hpp"

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/ply.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/segments/synthetic_surfaces.hpp"

namespace sarmap::segments {
namespace {

SegmentMap small_map() {
  PointBuffer points;
  std::uint32_t seed = 1;
  for (const auto& patch : testing::small_arena()) testing::add_patch(points, patch, 0.02, 0, seed++);
  SegmentSettings settings;
  settings.max_range = 0;
  SegmentMap map(settings);
  map.integrate(points, {2, 1, 0.5});
  return map;
}

TEST(SegmentFiles, JsonRoundTripKeepsEveryField) {
  test::ScratchFolder dir;
  const SegmentMap map = small_map();
  write_segments_json(dir / "segments.json", map);
  const SegmentsFile file = read_segments_json(dir / "segments.json");
  const auto live = map.segments();
  ASSERT_EQ(file.segments.size(), live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    const Segment& a = *live[i];
    const Segment& b = file.segments[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.label, b.label);
    EXPECT_EQ(a.inliers, b.inliers);
    EXPECT_TRUE(a.plane.normal.isApprox(b.plane.normal, 1e-12));
    EXPECT_NEAR(a.plane.offset, b.plane.offset, 1e-12);
    EXPECT_TRUE(a.rectangle.center.isApprox(b.rectangle.center, 1e-12));
    EXPECT_NEAR(a.rectangle.half_extents[0], b.rectangle.half_extents[0], 1e-12);
    EXPECT_TRUE(a.rectangle.axes[1].isApprox(b.rectangle.axes[1], 1e-12));
    EXPECT_NEAR(a.area_m2, b.area_m2, 1e-12);
    EXPECT_TRUE(a.min.isApprox(b.min, 1e-12));
  }
  std::ifstream in(dir / "segments.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["segments"][0]["class"], "terrain");
  EXPECT_EQ(j["segments"][0]["class_id"], 1);
}

TEST(SegmentFiles, PlyHoldsFourCornersPerSegmentInClassColours) {
  test::ScratchFolder dir;
  const SegmentMap map = small_map();
  write_segments_ply(dir / "segments.ply", map);
  const PointBuffer corners = read_ply(dir / "segments.ply");
  ASSERT_EQ(corners.size(), 4 * map.size());
  const Rgb wall = class_info(ClassId::Wall).color;
  std::size_t wall_corners = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) wall_corners += corners.red()[i] == wall.r && corners.green()[i] == wall.g;
  EXPECT_EQ(wall_corners, 4 * map.of_class(ClassId::Wall).size());
}

TEST(SegmentFiles, BadFilesNameWhatIsWrong) {
  test::ScratchFolder dir;
  auto message = [&](const std::string& text) {
    try {
      read_segments_json(dir.write("s.json", text));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(message(R"({"version": 2, "segments": []})").find("version"), std::string::npos);
  EXPECT_NE(message(R"({"version": 1, "segments": [{"id": 1}]})").find("segments[0]: missing \"class\""),
            std::string::npos);
  EXPECT_NE(message(R"({"version": 1, "segments": [{"id": 1, "class": "sofa"}]})").find("class name"),
            std::string::npos);
  EXPECT_THROW(read_segments_json(dir / "absent.json"), Error);
}

}  // namespace
}  // namespace sarmap::segments
