// Writes PLY point clouds with the plain header MeshLab and CloudCompare read:
// float x y z, then uchar red green blue, uchar label / gt_label, float
// nx ny nz, float intensity and float scalar_<name>, whichever the buffer has.
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/output_columns.hpp"
#include "engine/io/ply.hpp"

namespace sarmap {
namespace {

OutputColumn float_column(std::string name, std::span<const float> values) {
  return {std::move(name), ScalarType::Float32, values.data()};
}

OutputColumn byte_column(std::string name, std::span<const std::uint8_t> values) {
  return {std::move(name), ScalarType::UInt8, nullptr, values.data()};
}

std::vector<OutputColumn> ply_columns(const PointBuffer& points) {
  std::vector<OutputColumn> columns;
  columns.push_back(float_column("x", points.x()));
  columns.push_back(float_column("y", points.y()));
  columns.push_back(float_column("z", points.z()));
  if (points.has_colors()) {
    columns.push_back(byte_column("red", points.red()));
    columns.push_back(byte_column("green", points.green()));
    columns.push_back(byte_column("blue", points.blue()));
  }
  if (points.has_labels()) columns.push_back(byte_column("label", points.labels()));
  if (points.has_gt_labels()) columns.push_back(byte_column("gt_label", points.gt_labels()));
  if (points.has_normals()) {
    columns.push_back(float_column("nx", points.normal_x()));
    columns.push_back(float_column("ny", points.normal_y()));
    columns.push_back(float_column("nz", points.normal_z()));
  }
  if (points.has_intensity()) columns.push_back(float_column("intensity", points.intensity()));
  for (std::size_t s = 0; s < points.score_count(); ++s) {
    const std::string& name = points.score_names()[s];
    if (name.empty() || name.find_first_of(" \t\r\n") != std::string::npos) {
      throw Error(ErrorCode::InvalidArgument,
                  "score channel '" + name + "' cannot be a PLY property name (empty or has whitespace)");
    }
    columns.push_back(float_column("scalar_" + name, points.score(s)));
  }
  return columns;
}

}  // namespace

void write_ply(const std::filesystem::path& path, const PointBuffer& points, const PointCloudWriteOptions& options) {
  const std::vector<OutputColumn> columns = ply_columns(points);
  std::string header = "ply\nformat ";
  header += options.binary ? "binary_little_endian" : "ascii";
  header += " 1.0\ncomment written by sarmap\n";
  header += header_comment_lines(options.comments, "comment ", path);
  header += "element vertex ";
  header += std::to_string(points.size());
  header += '\n';
  for (const OutputColumn& c : columns) {
    header += "property ";
    header += c.type == ScalarType::UInt8 ? "uchar " : "float ";
    header += c.name;
    header += '\n';
  }
  header += "end_header\n";

  AtomicFileWriter out(path);
  out.write(header);
  if (options.binary) {
    write_binary_records(out, columns, points.size());
  } else {
    write_text_records(out, columns, points.size());
  }
  out.commit();
}

}  // namespace sarmap
