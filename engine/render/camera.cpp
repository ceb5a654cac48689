#include "engine/render/camera.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::render {
namespace {

constexpr float kPi = 3.14159265358979f;

void check_size(int width, int height) {
  if (width < 1 || height < 1) {
    throw Error(ErrorCode::InvalidArgument,
                "camera: image size " + std::to_string(width) + " x " + std::to_string(height) + " is empty");
  }
}

// Right and down axes of the image for a view along `forward`.
bool image_axes(const Eigen::Vector3f& forward, const Eigen::Vector3f& up, Eigen::Vector3f& right,
                Eigen::Vector3f& down) {
  right = forward.cross(up);
  if (!(right.norm() > 1e-6f)) return false;
  right.normalize();
  down = forward.cross(right);
  return true;
}

// The oblique view's direction from the box's centre towards the eye: from
// the south and a little west, about 45 degrees above the horizon, so the
// box's x side spans the wide frame, walls show a face and the floor between
// them stays visible.
const Eigen::Vector3f kObliqueFromCentre = Eigen::Vector3f(-0.3f, -1.0f, 1.0f).normalized();
constexpr float kObliqueFovDeg = 40.0f;
constexpr float kFrameMargin = 1.04f;

}  // namespace

Camera Camera::perspective(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                           const Eigen::Vector3f& up, float vertical_fov_deg, int width, int height) {
  check_size(width, height);
  if (!(vertical_fov_deg > 0 && vertical_fov_deg < 180)) {
    throw Error(ErrorCode::InvalidArgument, "camera: the field of view must lie in (0, 180) degrees");
  }
  Camera c;
  c.eye_ = eye;
  c.forward_ = target - eye;
  if (!(c.forward_.norm() > 0)) throw Error(ErrorCode::InvalidArgument, "camera: the eye is on its target");
  c.forward_.normalize();
  if (!image_axes(c.forward_, up, c.right_, c.down_)) {
    throw Error(ErrorCode::InvalidArgument, "camera: the up direction lies along the view");
  }
  c.scale_ = 0.5f * static_cast<float>(height) / std::tan(0.5f * vertical_fov_deg * kPi / 180.0f);
  c.width_ = width;
  c.height_ = height;
  return c;
}

Camera Camera::orthographic(const Eigen::Vector3f& center, const Eigen::Vector3f& forward,
                            const Eigen::Vector3f& up, float metres_per_pixel, float standoff, int width,
                            int height) {
  check_size(width, height);
  if (!(metres_per_pixel > 0) || !(forward.norm() > 0)) {
    throw Error(ErrorCode::InvalidArgument,
                "camera: an orthographic view needs a direction and a positive scale");
  }
  Camera c;
  c.orthographic_ = true;
  c.forward_ = forward.normalized();
  if (!image_axes(c.forward_, up, c.right_, c.down_)) {
    throw Error(ErrorCode::InvalidArgument, "camera: the up direction lies along the view");
  }
  c.eye_ = center - standoff * c.forward_;
  c.scale_ = metres_per_pixel;
  c.width_ = width;
  c.height_ = height;
  return c;
}

Camera::Ray Camera::ray(float x, float y) const {
  const float u = x - 0.5f * static_cast<float>(width_);
  const float v = y - 0.5f * static_cast<float>(height_);
  if (orthographic_) return {eye_ + scale_ * (u * right_ + v * down_), forward_};
  return {eye_, (scale_ * forward_ + u * right_ + v * down_).normalized()};
}

std::optional<Eigen::Vector2f> Camera::project(const Eigen::Vector3f& p) const {
  const Eigen::Vector3f d = p - eye_;
  const float depth = d.dot(forward_);
  float u = d.dot(right_), v = d.dot(down_);
  if (orthographic_) {
    u /= scale_;
    v /= scale_;
  } else {
    if (!(depth > 0)) return std::nullopt;
    u *= scale_ / depth;
    v *= scale_ / depth;
  }
  return Eigen::Vector2f(u + 0.5f * static_cast<float>(width_), v + 0.5f * static_cast<float>(height_));
}

Camera oblique_camera(const Box3& box, int width, int height) {
  check_size(width, height);
  const Eigen::Vector3f centre = 0.5f * (box.min + box.max);
  const Eigen::Vector3f forward = -kObliqueFromCentre;
  Eigen::Vector3f right, down;
  image_axes(forward, Eigen::Vector3f::UnitZ(), right, down);
  const float tan_v = std::tan(0.5f * kObliqueFovDeg * kPi / 180.0f);
  const float tan_h = tan_v * static_cast<float>(width) / static_cast<float>(height);
  // The nearest eye distance at which every corner is inside the frame: a
  // corner at offsets (a, b, c) along right, down and forward needs
  // |a| <= tan_h (distance + c) and |b| <= tan_v (distance + c).
  float distance = 0.1f;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3f p((corner & 1) ? box.max.x() : box.min.x(),
                            (corner & 2) ? box.max.y() : box.min.y(),
                            (corner & 4) ? box.max.z() : box.min.z());
    const Eigen::Vector3f d = p - centre;
    const float c = d.dot(forward);
    distance = std::max({distance, std::abs(d.dot(right)) / tan_h - c, std::abs(d.dot(down)) / tan_v - c});
  }
  distance *= kFrameMargin;
  return Camera::perspective(centre - distance * forward, centre, Eigen::Vector3f::UnitZ(), kObliqueFovDeg,
                             width, height);
}

Camera top_down_camera(const Box3& box, int width, int height) {
  check_size(width, height);
  const Eigen::Vector3f centre = 0.5f * (box.min + box.max);
  const Eigen::Vector3f size = (box.max - box.min).cwiseMax(1e-3f);
  const float metres_per_pixel =
      kFrameMargin * std::max(size.x() / static_cast<float>(width), size.y() / static_cast<float>(height));
  // Looking down (-z) with +y up the image puts +x to the right.
  return Camera::orthographic(centre, -Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitY(), metres_per_pixel,
                              size.z() + 1.0f, width, height);
}

}  // namespace sarmap::render
