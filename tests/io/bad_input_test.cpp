// Every broken file of tests/data/bad must fail with a sarmap::Error that
// names the file, where in it (line or byte offset) and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>

#include "engine/io/point_cloud_file.hpp"
#include "point_cloud_test_support.hpp"

namespace sarmap {
namespace {

using ::testing::HasSubstr;

struct BadFile {
  const char* file;
  ErrorCode code;
  const char* where;  // ":<line>: " or "(byte offset N)"
  const char* what;
};

class BadInput : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadInput, FailsWithAClearError) {
  const BadFile& bad = GetParam();
  const std::string path = test::data_path(std::string("bad/") + bad.file).string();
  const Error e = test::error_from([&] { read_point_cloud(path); });
  EXPECT_EQ(e.code(), bad.code) << e.what();
  EXPECT_THAT(e.what(), HasSubstr(path));
  EXPECT_THAT(e.what(), HasSubstr(path + bad.where));
  EXPECT_THAT(e.what(), HasSubstr(bad.what));
}

constexpr BadFile kPlyFiles[] = {
    {"ply_truncated_binary.ply", ErrorCode::Parse, " (byte offset 116)",
     "header declares 10 vertices of 12 bytes but only 62 bytes of data follow"},
    {"ply_count_too_large_ascii.ply", ErrorCode::Parse, ":11: ", "file ends after 3 of the 5 vertices"},
    {"ply_count_too_small_ascii.ply", ErrorCode::Parse, ":10: ", "data continues after the 2 vertices"},
    {"ply_non_numeric.ply", ErrorCode::Parse, ":9: ", "vertex 1: property 'y' is 'abc'; expected a number"},
    {"ply_too_few_values.ply", ErrorCode::Parse, ":9: ", "vertex 1: line ends before property 'z'"},
    {"ply_missing_z.ply", ErrorCode::Parse, ":3: ", "element vertex has no property 'z'"},
    {"ply_bad_type.ply", ErrorCode::Parse, ":5: ", "unknown property type 'float128'"},
    {"ply_color_not_uchar.ply", ErrorCode::Parse, ":7: ", "property 'red' has type float; expected uchar"},
    {"ply_huge_count.ply", ErrorCode::Parse, " (byte offset 126)", "header declares 999999999999 vertices"},
    {"ply_big_endian.ply", ErrorCode::Unsupported, ":2: ", "format binary_big_endian is not supported"},
    {"ply_no_end_header.ply", ErrorCode::Parse, ":4: ", "header ends without 'end_header'"},
    {"ply_not_ply.ply", ErrorCode::Parse, ":1: ", "not a PLY file"},
    {"ply_label_out_of_range.ply", ErrorCode::InvalidData, " (byte offset 162)",
     "property 'label' of vertex 1 is 300; expected a class id in 0..255"},
    {"ply_binary_trailing_bytes.ply", ErrorCode::Parse, " (byte offset 139)", "12 bytes follow the 2 vertices"},
    {"ply_truncated_list.ply", ErrorCode::Parse, " (byte offset 160)",
     "file ends inside list 'extra' of 200 items in record 0"},
    {"ply_no_vertex_element.ply", ErrorCode::Parse, ":5: ", "header declares no 'element vertex'"},
    {"ply_bad_count.ply", ErrorCode::Parse, ":3: ", "expected 'element <name> <count>'"},
};

constexpr BadFile kPcdFiles[] = {
    {"pcd_truncated_binary.pcd", ErrorCode::Parse, " (byte offset 166)",
     "header declares 10 points of 12 bytes but only 73 bytes of data follow"},
    {"pcd_points_mismatch.pcd", ErrorCode::Parse, ":10: ", "WIDTH * HEIGHT (5 * 1) does not equal POINTS (6)"},
    {"pcd_non_numeric.pcd", ErrorCode::Parse, ":13: ", "point 1: field 'z' is 'x'; expected a number"},
    {"pcd_missing_x.pcd", ErrorCode::Parse, ":3: ", "FIELDS has no 'x'"},
    {"pcd_bad_type_size.pcd", ErrorCode::Parse, ":5: ", "field 'y' has TYPE F with SIZE 2"},
    {"pcd_unknown_type.pcd", ErrorCode::Parse, ":5: ", "field 'y' has TYPE D with SIZE 4"},
    {"pcd_huge_points.pcd", ErrorCode::Parse, " (byte offset 186)", "header declares 999999999999 points"},
    {"pcd_huge_points_ascii.pcd", ErrorCode::Parse, ":10: ", "header declares 999999999999 points"},
    {"pcd_size_count_mismatch.pcd", ErrorCode::Parse, ":4: ", "SIZE has 2 entries; expected one per field (3)"},
    {"pcd_no_data_line.pcd", ErrorCode::Parse, ":10: ", "header ends without a DATA line"},
    {"pcd_count_too_large_ascii.pcd", ErrorCode::Parse, ":14: ", "file ends after 3 of the 5 points"},
    {"pcd_count_too_small_ascii.pcd", ErrorCode::Parse, ":14: ", "data continues after the 2 points"},
    {"pcd_label_count.pcd", ErrorCode::Parse, ":6: ", "field 'label' has COUNT 2; expected 1"},
    {"pcd_bad_data_kind.pcd", ErrorCode::Parse, ":11: ",
     "DATA 'binary_lzma'; expected ascii, binary or binary_compressed"},
    // Zero bytes after the points are padding (PCL writes them); these are a third point.
    {"pcd_binary_trailing_bytes.pcd", ErrorCode::Parse, " (byte offset 188)",
     "12 bytes follow the 2 points the header declares and the one at byte offset 191 is not zero"},
    {"pcd_compressed_bad_reference.pcd", ErrorCode::Parse, " (byte offset 183)",
     "LZF data (byte 0 of the compressed block): back-reference 200 bytes back reaches before the start"},
    {"pcd_compressed_size_too_large.pcd", ErrorCode::Parse, " (byte offset 183)",
     "compressed size is 5000 bytes but only 25 bytes follow"},
    {"pcd_compressed_wrong_uncompressed_size.pcd", ErrorCode::Parse, " (byte offset 179)",
     "uncompressed size is 36 bytes; expected POINTS * point size = 2 * 12"},
    {"pcd_compressed_truncated_stream.pcd", ErrorCode::Parse, " (byte offset 183)",
     "literal run of 24 bytes is cut off"},
    {"pcd_compressed_missing_sizes.pcd", ErrorCode::Parse, " (byte offset 175)",
     "file ends before the binary_compressed sizes"},
};

std::string test_name(const ::testing::TestParamInfo<BadFile>& info) {
  std::string name = info.param.file;
  for (char& c : name) {
    if (c == '.') c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Ply, BadInput, ::testing::ValuesIn(kPlyFiles), test_name);
INSTANTIATE_TEST_SUITE_P(Pcd, BadInput, ::testing::ValuesIn(kPcdFiles), test_name);

TEST(BadInputCorpus, EveryFileInTheFolderHasACase) {
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::data_path("bad"))) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".ply" || ext == ".pcd") ++files;
  }
  EXPECT_EQ(files, std::size(kPlyFiles) + std::size(kPcdFiles));
}

}  // namespace
}  // namespace sarmap
