// A point buffer's part of a checkpoint: the point count, then each array
// behind a flag saying whether the attribute is enabled.
#include <string>

#include "engine/core/point_buffer.hpp"

namespace sarmap {
namespace {

template <class T>
void put_span(StateWriter& out, std::span<const T> values) {
  out.put_vector(std::vector<T>(values.begin(), values.end()));
}

template <class T>
void get_span(StateReader& in, std::span<T> into, const char* name) {
  const std::vector<T> values = in.get_vector<T>();
  if (values.size() != into.size()) in.fail(std::string("point attribute ") + name + " has the wrong length");
  std::copy(values.begin(), values.end(), into.begin());
}

}  // namespace

void PointBuffer::save_state(StateWriter& out) const {
  out.tag("PNTS");
  out.put<std::uint64_t>(size());
  put_span(out, x()), put_span(out, y()), put_span(out, z());
  const bool flags[5] = {has_labels_, has_gt_labels_, has_colors_, has_intensity_, has_normals_};
  for (bool f : flags) out.put<std::uint8_t>(f);
  if (has_labels_) put_span(out, labels());
  if (has_gt_labels_) put_span(out, gt_labels());
  if (has_colors_) put_span(out, red()), put_span(out, green()), put_span(out, blue());
  if (has_intensity_) put_span(out, intensity());
  if (has_normals_) put_span(out, normal_x()), put_span(out, normal_y()), put_span(out, normal_z());
  out.put<std::uint64_t>(score_count());
  for (std::size_t c = 0; c < score_count(); ++c) {
    out.put_string(score_names_[c]);
    put_span(out, score(c));
  }
}

void PointBuffer::load_state(StateReader& in) {
  in.expect_tag("PNTS");
  PointBuffer loaded(in.get_count(12));
  get_span(in, loaded.x(), "x"), get_span(in, loaded.y(), "y"), get_span(in, loaded.z(), "z");
  bool flags[5];
  for (bool& f : flags) f = in.get<std::uint8_t>() != 0;
  if (flags[0]) loaded.enable_labels(), get_span(in, loaded.labels(), "label");
  if (flags[1]) loaded.enable_gt_labels(), get_span(in, loaded.gt_labels(), "gt_label");
  if (flags[2]) {
    loaded.enable_colors();
    get_span(in, loaded.red(), "red"), get_span(in, loaded.green(), "green"), get_span(in, loaded.blue(), "blue");
  }
  if (flags[3]) loaded.enable_intensity(), get_span(in, loaded.intensity(), "intensity");
  if (flags[4]) {
    loaded.enable_normals();
    get_span(in, loaded.normal_x(), "nx"), get_span(in, loaded.normal_y(), "ny"), get_span(in, loaded.normal_z(), "nz");
  }
  const std::size_t channels = in.get_count(16);
  for (std::size_t c = 0; c < channels; ++c) {
    const std::string name = in.get_string();
    if (loaded.find_score(name) != loaded.score_count()) in.fail("score channel " + name + " saved twice");
    get_span(in, loaded.score(loaded.add_score(name)), "score");
  }
  *this = std::move(loaded);
}

}  // namespace sarmap
