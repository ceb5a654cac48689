// Flat 2-D drawing on an RgbImage for the top view's overlays: thick lines,
// filled discs and polygon outlines, clipped to the image. A pixel is
// painted when its centre lies inside the shape; no anti-aliasing, so a test
// can say exactly which pixels a shape covers.
#pragma once

#include <span>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/render/rgb_image.hpp"

namespace sarmap::render {

// Every pixel whose centre lies within width / 2 of the segment a-b (image
// coordinates: pixel (i, j) covers [i, i + 1) x [j, j + 1)).
void draw_line(RgbImage& image, const Eigen::Vector2f& a, const Eigen::Vector2f& b, float width, Rgb color);

// Every pixel whose centre lies within `radius` of `center`.
void fill_disc(RgbImage& image, const Eigen::Vector2f& center, float radius, Rgb color);

// The closed outline through the corners, each side a draw_line.
void draw_polygon(RgbImage& image, std::span<const Eigen::Vector2f> corners, float width, Rgb color);

}  // namespace sarmap::render
