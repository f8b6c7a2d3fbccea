#pragma once
// A pinhole camera: position, target, up and vertical field of view. Pixel (x, y) has its top-left
// corner at (x, y), row 0 at the top; pixel values are the radiance along each ray (no exposure).

#include "libvdbappear/medium/medium_view.h"  // Aabb
#include "libvdbappear/render/ray.h"

#include <string>

namespace vdbappear {

struct CameraPose {
  Vec3 position = Vec3(0, -4, 0);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3(0, 0, 1);
  double fov_degrees = 30;  // vertical
};

class PinholeCamera {
 public:
  // Throws std::invalid_argument when position = target or up is parallel to the view direction.
  PinholeCamera(const CameraPose& pose, int width, int height);
  // The ray through image point (x, y) in pixels, x in [0, width), y in [0, height).
  Ray ray(double x, double y) const;

 private:
  Vec3 position_, forward_, right_, up_;
  double tan_half_fov_, aspect_;
  int width_, height_;
};

// --view SIDE (+x, -x, +y, -y, +z, -z): looks at the box's centre from that side, along the axis,
// from the distance at which the whole box fits the image (the six training views of Fig. 7,
// downsampling paper). Up is +z for the x and y sides and +y for the z sides.
CameraPose framedView(const Aabb& box, const std::string& side, double fov_degrees, double aspect);

// Looks at the box's centre from the unit direction `toward_camera` (up: `up`, not parallel to it),
// from the nearest distance at which all eight corners fit the image.
CameraPose framedDirection(const Aabb& box, const Vec3& toward_camera, const Vec3& up, double fov_degrees, double aspect);
// Width / height of the box's outline seen from `toward_camera` (orthographic), for image sizes.
double outlineAspect(const Aabb& box, const Vec3& toward_camera, const Vec3& up);

}  // namespace vdbappear
