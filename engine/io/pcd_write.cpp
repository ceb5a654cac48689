// Writes PCD v0.7 point clouds as PCL writes them: fields x y z (F 4), rgb
// (U 4, 0x00RRGGBB), label / gt_label (U 4, as PCL's PointXYZL has it),
// normal_x/y/z and intensity (F 4), scalar_<name> (F 4); DATA ascii, binary or
// binary_compressed.
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/lzf.hpp"
#include "engine/io/output_columns.hpp"
#include "engine/io/pcd.hpp"

namespace sarmap {
namespace {

OutputColumn float_column(std::string name, std::span<const float> values) {
  return {std::move(name), ScalarType::Float32, values.data()};
}

OutputColumn wide_label_column(std::string name, std::span<const std::uint8_t> values) {
  return {std::move(name), ScalarType::UInt32, nullptr, values.data()};
}

std::vector<OutputColumn> pcd_columns(const PointBuffer& points) {
  std::vector<OutputColumn> columns;
  columns.push_back(float_column("x", points.x()));
  columns.push_back(float_column("y", points.y()));
  columns.push_back(float_column("z", points.z()));
  if (points.has_colors()) {
    columns.push_back(
        {"rgb", ScalarType::UInt32, nullptr, points.red().data(), points.green().data(), points.blue().data()});
  }
  if (points.has_labels()) columns.push_back(wide_label_column("label", points.labels()));
  if (points.has_gt_labels()) columns.push_back(wide_label_column("gt_label", points.gt_labels()));
  if (points.has_normals()) {
    columns.push_back(float_column("normal_x", points.normal_x()));
    columns.push_back(float_column("normal_y", points.normal_y()));
    columns.push_back(float_column("normal_z", points.normal_z()));
  }
  if (points.has_intensity()) columns.push_back(float_column("intensity", points.intensity()));
  for (std::size_t s = 0; s < points.score_count(); ++s) {
    const std::string& name = points.score_names()[s];
    if (name.empty() || name.find_first_of(" \t\r\n") != std::string::npos) {
      throw Error(ErrorCode::InvalidArgument,
                  "score channel '" + name + "' cannot be a PCD field name (empty or has whitespace)");
    }
    columns.push_back(float_column("scalar_" + name, points.score(s)));
  }
  return columns;
}

std::string pcd_header(const std::vector<OutputColumn>& columns, std::size_t count, std::string_view data,
                       const std::string& comments) {
  std::string fields = "FIELDS", sizes = "SIZE", types = "TYPE", counts = "COUNT";
  for (const OutputColumn& c : columns) {
    fields += ' ' + c.name;
    sizes += ' ' + std::to_string(scalar_size(c.type));
    types += ' ';
    types += pcd_type_letter(c.type);
    counts += " 1";
  }
  const std::string n = std::to_string(count);
  return "# .PCD v0.7 - Point Cloud Data file format\n" + comments + "VERSION 0.7\n" + fields + '\n' + sizes +
         '\n' + types + '\n' + counts + "\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n +
         "\nDATA " + std::string(data) + '\n';
}

}  // namespace

void write_pcd(const std::filesystem::path& path, const PointBuffer& points, const PointCloudWriteOptions& options) {
  const std::vector<OutputColumn> columns = pcd_columns(points);
  const std::size_t count = points.size();
  const bool compressed = options.binary && options.compressed;
  const std::string comments = header_comment_lines(options.comments, "# ", path);
  AtomicFileWriter out(path);
  if (!options.binary) {
    out.write(pcd_header(columns, count, "ascii", comments));
    write_text_records(out, columns, count);
  } else if (!compressed) {
    out.write(pcd_header(columns, count, "binary", comments));
    write_binary_records(out, columns, count);
  } else {
    const std::size_t size = count * record_size(columns);
    if (size > UINT32_MAX) {
      throw Error(ErrorCode::OutOfRange, path.string() + ": " + std::to_string(size) +
                                             " bytes of points exceed binary_compressed's 32-bit size field");
    }
    std::vector<std::uint8_t> unpacked(size);
    encode_binary_columns(columns, count, reinterpret_cast<char*>(unpacked.data()));
    const std::vector<std::uint8_t> packed = lzf_compress(unpacked);
    const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(packed.size()), static_cast<std::uint32_t>(size)};
    out.write(pcd_header(columns, count, "binary_compressed", comments));
    out.write(sizes, sizeof(sizes));
    out.write(packed.data(), packed.size());
  }
  out.commit();
}

}  // namespace sarmap
