// A camera for ray-cast pictures: the ray through each pixel and where a
// world point lands in the image (x to the right, y down, pixel (i, j)
// covering [i, i + 1) x [j, j + 1)). Perspective for the oblique 3-D views,
// orthographic for the top view, and the framing of a box in either.
#pragma once

#include <optional>

#include <Eigen/Core>

namespace sarmap::render {

// An axis-aligned box in world coordinates (metres).
struct Box3 {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
};

class Camera {
 public:
  struct Ray {
    Eigen::Vector3f origin;
    Eigen::Vector3f direction;  // unit length
  };

  // Looking from `eye` at `target`, `up` roughly up the image, with this
  // vertical field of view. Throws sarmap::Error (InvalidArgument) for a
  // size below one pixel, eye == target, an up along the view, or a field of
  // view outside (0, 180) degrees.
  static Camera perspective(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                            const Eigen::Vector3f& up, float vertical_fov_deg, int width, int height);
  // Parallel rays along `forward`, the image centred on `center` (rays start
  // `standoff` metres behind it), `metres_per_pixel` a side.
  static Camera orthographic(const Eigen::Vector3f& center, const Eigen::Vector3f& forward,
                             const Eigen::Vector3f& up, float metres_per_pixel, float standoff, int width,
                             int height);

  int width() const { return width_; }
  int height() const { return height_; }

  // The ray through image point (x, y); a pixel's centre is (i + 0.5, j + 0.5).
  Ray ray(float x, float y) const;
  // Where p lands in the image; nullopt when it is not in front of the camera.
  std::optional<Eigen::Vector2f> project(const Eigen::Vector3f& p) const;
  // The width in metres that one pixel covers at distance t along a ray.
  float pixel_footprint(float t) const { return orthographic_ ? scale_ : t / scale_; }

 private:
  Camera() = default;
  bool orthographic_ = false;
  Eigen::Vector3f eye_, forward_, right_, down_;
  // Perspective: focal length in pixels. Orthographic: metres per pixel.
  float scale_ = 1;
  int width_ = 0, height_ = 0;
};

// The oblique view of paper 000's figures: from above the box's south-west
// side, looking down at its centre, the whole box in the frame.
Camera oblique_camera(const Box3& box, int width, int height);
// Straight down, x to the right and y up the image, the box's footprint
// filling the frame less a small margin.
Camera top_down_camera(const Box3& box, int width, int height);

}  // namespace sarmap::render
