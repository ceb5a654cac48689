#include "engine/topo/ros_map_files.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/text_parse.hpp"

namespace sarmap::topo {
namespace {

// Shortest text that reads back to the same double, with ".0" added to whole
// numbers so a YAML reader cannot take them for integers.
std::string number_text(double value) {
  std::array<char, 64> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  std::string text(buffer.data(), end);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

bool is_plain_file_name(std::string_view stem) {
  if (stem.empty() || stem == "." || stem == "..") return false;
  for (const char c : stem) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::uint8_t pixel_of(CellState state) {
  switch (state) {
    case CellState::Free:
      return kRosFreePixel;
    case CellState::Occupied:
      return kRosOccupiedPixel;
    case CellState::Unknown:
      return kRosUnknownPixel;
  }
  return kRosUnknownPixel;
}

// ---- reading the YAML ----

struct YamlFields {
  std::optional<std::string> image;
  std::optional<double> resolution;
  std::optional<std::array<double, 3>> origin;
  std::optional<std::int64_t> negate;
  std::optional<double> occupied_thresh;
  std::optional<double> free_thresh;
  std::optional<std::string> mode;
};

// A '#' starts a comment at the start of a line or after a blank, outside quotes (as in YAML).
std::string_view without_comment(std::string_view line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
      return line.substr(0, i);
    }
  }
  return line;
}

std::string_view unquoted(std::string_view value) {
  if (value.size() >= 2 && (value.front() == '\'' || value.front() == '"') && value.back() == value.front()) {
    return value.substr(1, value.size() - 2);
  }
  return value;
}

class YamlReader {
 public:
  explicit YamlReader(const std::filesystem::path& path) : name_(path.string()) {}

  [[noreturn]] void fail(std::size_t line, std::string_view message,
                         ErrorCode code = ErrorCode::Parse) const {
    throw Error(code, at_line(name_, line, message));
  }

  double number(std::size_t line, std::string_view key, std::string_view text) const {
    double value = 0.0;
    if (!parse_number(trim(text), value) || !std::isfinite(value)) {
      fail(line, std::string(key) + ": '" + std::string(text) + "' is not a finite number");
    }
    return value;
  }

  YamlFields parse(std::string_view text) {
    YamlFields fields;
    LineReader lines(text);
    std::string_view raw;
    while (lines.next(raw)) {
      const std::size_t line = lines.line_number();
      const std::string_view content = trim(without_comment(raw));
      if (content.empty() || content == "---" || content == "...") continue;
      const std::size_t colon = content.find(':');
      if (colon == std::string_view::npos)
        fail(line, "expected 'key: value', found '" + std::string(content) + "'");
      const std::string key(trim(content.substr(0, colon)));
      const std::string_view value = unquoted(trim(content.substr(colon + 1)));
      const auto once = [&](auto& field, auto parsed) {
        if (field) fail(line, "'" + key + "' is given twice");
        field = parsed;
      };
      if (key == "image") {
        if (value.empty()) fail(line, "image: the image file name is empty");
        once(fields.image, std::string(value));
      } else if (key == "resolution") {
        once(fields.resolution, number(line, key, value));
      } else if (key == "origin") {
        once(fields.origin, origin(line, value));
      } else if (key == "negate") {
        std::int64_t negate = 0;
        if (!parse_number(value, negate) || (negate != 0 && negate != 1)) {
          fail(line, "negate: expected 0 or 1, found '" + std::string(value) + "'");
        }
        once(fields.negate, negate);
      } else if (key == "occupied_thresh") {
        once(fields.occupied_thresh, number(line, key, value));
      } else if (key == "free_thresh") {
        once(fields.free_thresh, number(line, key, value));
      } else if (key == "mode") {
        once(fields.mode, std::string(value));
      }
      // Other keys (map_server ignores them too) are skipped.
    }
    return fields;
  }

 private:
  std::array<double, 3> origin(std::size_t line, std::string_view value) const {
    if (value.size() < 2 || value.front() != '[' || value.back() != ']') {
      fail(line, "origin: expected [x, y, yaw], found '" + std::string(value) + "'");
    }
    std::string_view rest = value.substr(1, value.size() - 2);
    std::array<double, 3> xyz{};
    for (std::size_t i = 0; i < 3; ++i) {
      const std::size_t comma = rest.find(',');
      if ((i < 2) != (comma != std::string_view::npos)) {
        fail(line, "origin: expected three numbers [x, y, yaw], found '" + std::string(value) + "'");
      }
      xyz[i] = number(line, "origin", rest.substr(0, comma));
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
    return xyz;
  }

  std::string name_;
};

// ---- reading the PGM ----

class PgmReader {
 public:
  PgmReader(const std::filesystem::path& path, std::string_view bytes)
      : name_(path.string()), bytes_(bytes) {}

  [[noreturn]] void fail(std::string_view message, ErrorCode code = ErrorCode::Parse) const {
    throw Error(code, at_offset(name_, position_, message));
  }

  // Header tokens may be separated by any whitespace and '#' comments to the end of a line.
  void skip_blanks_and_comments() {
    while (position_ < bytes_.size()) {
      const char c = bytes_[position_];
      if (c == '#') {
        while (position_ < bytes_.size() && bytes_[position_] != '\n') ++position_;
      } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f') {
        ++position_;
      } else {
        return;
      }
    }
  }

  std::uint64_t header_number(std::string_view what) {
    skip_blanks_and_comments();
    std::uint64_t value = 0;
    const char* first = bytes_.data() + position_;
    const auto [end, error] = std::from_chars(first, bytes_.data() + bytes_.size(), value);
    if (error != std::errc() || end == first)
      fail("expected the " + std::string(what) + " in the PGM header");
    position_ += static_cast<std::size_t>(end - first);
    return value;
  }

  struct Image {
    int width = 0;
    int height = 0;
    std::uint64_t maxval = 0;
    std::string_view pixels;  // rows top to bottom
  };

  Image read() {
    if (bytes_.size() < 2 || bytes_[0] != 'P') fail("not a PGM file (no 'P5' magic)");
    if (bytes_[1] != '5') {
      fail(std::string("a Netpbm 'P") + bytes_[1] + "' file: only binary 8-bit PGM (P5) is read",
           ErrorCode::Unsupported);
    }
    position_ = 2;
    Image image;
    const std::uint64_t width = header_number("width");
    const std::uint64_t height = header_number("height");
    if (width == 0 || height == 0 || width * height >= (std::uint64_t{1} << 31) || width > (1u << 31) ||
        height > (1u << 31)) {
      fail("a PGM of " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels (both must be positive, the product below 2^31)");
    }
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    image.maxval = header_number("maximum value");
    if (image.maxval == 0 || image.maxval > 65535) fail("the PGM's maximum value must be 1 to 65535");
    if (image.maxval > 255)
      fail("a 16-bit PGM: only 8-bit PGMs (maximum value <= 255) are read", ErrorCode::Unsupported);
    // Exactly one whitespace byte ends the header; the next byte is a pixel even if it looks like a blank.
    if (position_ >= bytes_.size() || !(bytes_[position_] == ' ' || bytes_[position_] == '\t' ||
                                        bytes_[position_] == '\n' || bytes_[position_] == '\r')) {
      fail("expected one whitespace byte after the PGM's maximum value");
    }
    ++position_;
    const std::size_t expected = static_cast<std::size_t>(width * height);
    if (bytes_.size() - position_ != expected) {
      fail("the PGM holds " + std::to_string(bytes_.size() - position_) + " bytes of pixels, " +
           std::to_string(width) + " x " + std::to_string(height) + " needs " + std::to_string(expected));
    }
    image.pixels = bytes_.substr(position_);
    return image;
  }

 private:
  std::string name_;
  std::string_view bytes_;
  std::size_t position_ = 0;
};

}  // namespace

std::string ros_map_yaml(const PlanningGrid& grid, std::string_view image_name) {
  std::string yaml;
  yaml += "image: ";
  yaml += image_name;
  yaml += "\nresolution: " + number_text(grid.resolution());
  yaml += "\norigin: [" + number_text(grid.origin().x()) + ", " + number_text(grid.origin().y()) + ", 0.0]";
  yaml += "\nnegate: 0";
  yaml += "\noccupied_thresh: " + number_text(kRosOccupiedThreshold);
  yaml += "\nfree_thresh: " + number_text(kRosFreeThreshold);
  yaml += "\n";
  return yaml;
}

RosMapPaths write_ros_map(const PlanningGrid& grid, const std::filesystem::path& folder,
                          std::string_view stem) {
  if (!is_plain_file_name(stem)) {
    throw Error(ErrorCode::InvalidArgument, "topo: the map's file stem '" + std::string(stem) +
                                                "' may hold only letters, digits, '.', '_' and '-'");
  }
  if (grid.width() <= 0) throw Error(ErrorCode::InvalidArgument, "topo: cannot write an empty planning grid");
  RosMapPaths paths{folder / (std::string(stem) + ".pgm"), folder / (std::string(stem) + ".yaml")};

  std::string header =
      "P5\n" + std::to_string(grid.width()) + " " + std::to_string(grid.height()) + "\n255\n";
  std::vector<std::uint8_t> pixels(grid.cells().size());
  for (int row = 0; row < grid.height(); ++row) {
    // map_server puts the image's first row at the top, the highest y.
    const int y = grid.height() - 1 - row;
    for (int x = 0; x < grid.width(); ++x) {
      pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.width()) +
             static_cast<std::size_t>(x)] = pixel_of(grid.at({x, y}));
    }
  }
  {
    AtomicFileWriter image(paths.image);
    image.write(header);
    image.write(pixels.data(), pixels.size());
    image.commit();
  }
  {
    AtomicFileWriter yaml(paths.yaml);
    yaml.write(ros_map_yaml(grid, paths.image.filename().string()));
    yaml.commit();
  }
  return paths;
}

PlanningGrid read_ros_map(const std::filesystem::path& yaml_path) {
  const FileBytes yaml_bytes = read_file_bytes(yaml_path);
  YamlReader yaml(yaml_path);
  const YamlFields fields = yaml.parse(yaml_bytes.view());
  const auto require = [&](const auto& field, std::string_view key) {
    if (!field) yaml.fail(0, "missing the key '" + std::string(key) + "'");
  };
  require(fields.image, "image");
  require(fields.resolution, "resolution");
  require(fields.origin, "origin");
  require(fields.negate, "negate");
  require(fields.occupied_thresh, "occupied_thresh");
  require(fields.free_thresh, "free_thresh");
  if (fields.mode && *fields.mode != "trinary") {
    yaml.fail(0, "mode '" + *fields.mode + "': only trinary maps are read", ErrorCode::Unsupported);
  }
  if (*fields.resolution <= 0.0) yaml.fail(0, "resolution must be > 0");
  if ((*fields.origin)[2] != 0.0) {
    yaml.fail(0, "origin yaw " + number_text((*fields.origin)[2]) + ": rotated maps are not supported",
              ErrorCode::Unsupported);
  }
  const double occupied_thresh = *fields.occupied_thresh;
  const double free_thresh = *fields.free_thresh;
  if (free_thresh < 0.0 || occupied_thresh > 1.0 || free_thresh > occupied_thresh) {
    yaml.fail(0, "thresholds must satisfy 0 <= free_thresh <= occupied_thresh <= 1");
  }

  std::filesystem::path image_path = *fields.image;
  if (image_path.is_relative()) image_path = yaml_path.parent_path() / image_path;
  const FileBytes image_bytes = read_file_bytes(image_path);
  const PgmReader::Image image = PgmReader(image_path, image_bytes.view()).read();

  PlanningGrid grid(image.width, image.height, *fields.resolution,
                    Eigen::Vector2d((*fields.origin)[0], (*fields.origin)[1]), CellState::Unknown);
  const double maxval = static_cast<double>(image.maxval);
  for (int row = 0; row < image.height; ++row) {
    for (int x = 0; x < image.width; ++x) {
      const auto value = static_cast<std::uint8_t>(
          image.pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                       static_cast<std::size_t>(x)]);
      const double darkness = *fields.negate != 0 ? value / maxval : (maxval - value) / maxval;
      CellState state = CellState::Unknown;
      if (darkness > occupied_thresh) {
        state = CellState::Occupied;
      } else if (darkness < free_thresh) {
        state = CellState::Free;
      }
      grid.set({x, image.height - 1 - row}, state);
    }
  }
  return grid;
}

}  // namespace sarmap::topo
