#include "engine/render/raster.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sarmap::render {
namespace {

// The pixel range whose centres may lie within [lo, hi], clipped to [0, size).
void pixel_span(double lo, double hi, int size, int& first, int& last) {
  // Clamped before the cast: a point far off the image must not overflow int.
  const double top = size;
  first = static_cast<int>(std::floor(std::clamp(lo - 0.5, 0.0, top)));
  last = std::min(size - 1, static_cast<int>(std::ceil(std::clamp(hi - 0.5, -1.0, top))));
}

// Cuts the segment a-b to the box [lo, hi], one side of the box at a time,
// the cut end put exactly on that side; false when nothing of it is inside.
// So a far-off end point costs no precision along the side it was cut to.
bool clip(Eigen::Vector2d& a, Eigen::Vector2d& b, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  for (int axis = 0; axis < 2; ++axis) {
    for (const bool low_side : {true, false}) {
      const double bound = low_side ? lo[axis] : hi[axis];
      const auto outside = [&](const Eigen::Vector2d& p) {
        return low_side ? p[axis] < bound : p[axis] > bound;
      };
      const bool a_out = outside(a), b_out = outside(b);
      if (a_out && b_out) return false;
      if (!a_out && !b_out) continue;
      Eigen::Vector2d& end = a_out ? a : b;
      const Eigen::Vector2d& kept = a_out ? b : a;
      const double s = (bound - kept[axis]) / (end[axis] - kept[axis]);
      end = kept + s * (end - kept);
      end[axis] = bound;
    }
  }
  return true;
}

}  // namespace

void draw_line(RgbImage& image, const Eigen::Vector2f& a, const Eigen::Vector2f& b, float width, Rgb color) {
  if (!a.allFinite() || !b.allFinite() || !(width > 0)) return;
  const double r = 0.5 * width;
  Eigen::Vector2d from = a.cast<double>(), to = b.cast<double>();
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(r + 1);
  if (!clip(from, to, -margin, Eigen::Vector2d(image.width(), image.height()) + margin)) return;
  int x0, x1, y0, y1;
  pixel_span(std::min(from.x(), to.x()) - r, std::max(from.x(), to.x()) + r, image.width(), x0, x1);
  pixel_span(std::min(from.y(), to.y()) - r, std::max(from.y(), to.y()) + r, image.height(), y0, y1);
  const Eigen::Vector2d d = to - from;
  const double length2 = d.squaredNorm();
  // Every pixel within r of the segment lies within r of its line, whose
  // band crosses a row in a run r |d| / |d.y| to either side of the line: only
  // that run of each row is tested, not the whole bounding box, so a long
  // diagonal costs its length, not its box's area.
  const double run = std::abs(d.y()) > 0 ? r * std::sqrt(length2) / std::abs(d.y()) : 0;
  for (int y = y0; y <= y1; ++y) {
    const double row = y + 0.5;
    int first = x0, last = x1;
    if (std::abs(d.y()) > 0) {
      const double across = from.x() + (row - from.y()) * d.x() / d.y();
      int a0, a1;
      pixel_span(across - run, across + run, image.width(), a0, a1);
      first = std::max(first, a0);
      last = std::min(last, a1);
    }
    for (int x = first; x <= last; ++x) {
      const Eigen::Vector2d p(x + 0.5, row);
      const double s = length2 > 0 ? std::clamp((p - from).dot(d) / length2, 0.0, 1.0) : 0.0;
      if ((p - (from + s * d)).squaredNorm() <= r * r) image.set(x, y, color);
    }
  }
}

void fill_disc(RgbImage& image, const Eigen::Vector2f& center, float radius, Rgb color) {
  draw_line(image, center, center, 2 * radius, color);
}

void draw_polygon(RgbImage& image, std::span<const Eigen::Vector2f> corners, float width, Rgb color) {
  for (std::size_t i = 0; i < corners.size(); ++i) {
    draw_line(image, corners[i], corners[(i + 1) % corners.size()], width, color);
  }
}

}  // namespace sarmap::render
