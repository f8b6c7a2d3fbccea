#include "libvdbappear/render/camera.h"

#include "libvdbappear/math/constants.h"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

PinholeCamera::PinholeCamera(const CameraPose& pose, int width, int height)
    : position_(pose.position), width_(width), height_(height) {
  const Vec3 view = pose.target - pose.position;
  if (!(view.norm() > 0)) throw std::invalid_argument("camera: position and target coincide");
  if (!(pose.fov_degrees > 0 && pose.fov_degrees < 180)) throw std::invalid_argument("camera: --fov must lie in (0, 180) degrees");
  forward_ = view.normalized();
  right_ = forward_.cross(pose.up);
  if (!(right_.norm() > 1e-9 * pose.up.norm())) throw std::invalid_argument("camera: up is parallel to the view direction");
  right_.normalize();
  up_ = right_.cross(forward_);
  tan_half_fov_ = std::tan(pose.fov_degrees * kPi / 360);
  aspect_ = double(width) / height;
}

Ray PinholeCamera::ray(double x, double y) const {
  const double sx = (2 * x / width_ - 1) * tan_half_fov_ * aspect_;
  const double sy = (1 - 2 * y / height_) * tan_half_fov_;
  const Vec3 d = (forward_ + sx * right_ + sy * up_).normalized();
  // A pixel is (2 tan(fov/2) / height)^2 of the image plane at distance 1; seen from the camera at
  // angle alpha off axis it subtends that times cos^3 alpha.
  const double cos_alpha = d.dot(forward_);
  return {position_, d, 2 * tan_half_fov_ / height_ * cos_alpha * std::sqrt(cos_alpha)};  // cos^1.5
}

CameraPose framedView(const Aabb& box, const std::string& side, double fov_degrees, double aspect) {
  if (side.size() != 2 || (side[0] != '+' && side[0] != '-') || side[1] < 'x' || side[1] > 'z')
    throw std::invalid_argument("--view '" + side + "': expected +x, -x, +y, -y, +z or -z");
  const int axis = side[1] - 'x';
  const double sign = side[0] == '+' ? 1 : -1;
  Vec3 direction = Vec3::Zero();
  direction[axis] = sign;
  CameraPose pose;
  pose.fov_degrees = fov_degrees;
  pose.up = axis == 2 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
  pose.target = box.centre();
  // The box's half extents across the image, and its half depth along the view.
  const Vec3 half = box.extent() / 2;
  const Vec3 right = (-direction).cross(pose.up);
  const double half_w = half.dot(right.cwiseAbs()), half_h = half.dot(pose.up.cwiseAbs()), half_depth = half[axis];
  const double tan_v = std::tan(fov_degrees * kPi / 360), tan_h = tan_v * aspect;
  const double distance = half_depth + 1.05 * std::max(half_w / tan_h, half_h / tan_v);
  pose.position = pose.target + distance * direction;
  return pose;
}

namespace {

// The camera frame of a view from `toward_camera`: right, up (image axes).
std::pair<Vec3, Vec3> imageAxes(const Vec3& toward_camera, const Vec3& up) {
  const Vec3 forward = -toward_camera.normalized();
  const Vec3 right = forward.cross(up);
  if (!(right.norm() > 1e-9)) throw std::invalid_argument("framing: up is parallel to the view direction");
  return {right.normalized(), right.normalized().cross(forward)};
}

Vec3 corner(const Aabb& box, int c) {
  return {c & 1 ? box.hi.x() : box.lo.x(), c & 2 ? box.hi.y() : box.lo.y(), c & 4 ? box.hi.z() : box.lo.z()};
}

}  // namespace

CameraPose framedDirection(const Aabb& box, const Vec3& toward_camera, const Vec3& up, double fov_degrees, double aspect) {
  const auto [right, image_up] = imageAxes(toward_camera, up);
  const Vec3 d = toward_camera.normalized();
  const double tan_v = std::tan(fov_degrees * kPi / 360), tan_h = tan_v * aspect;
  double distance = 0;
  for (int c = 0; c < 8; ++c) {  // corner at depth z toward the camera must fit: |x| <= (D - z) tan
    const Vec3 q = corner(box, c) - box.centre();
    const double z = q.dot(d);
    distance = std::max({distance, z + 1.05 * std::abs(q.dot(right)) / tan_h, z + 1.05 * std::abs(q.dot(image_up)) / tan_v});
  }
  CameraPose pose;
  pose.fov_degrees = fov_degrees;
  pose.up = up;
  pose.target = box.centre();
  pose.position = pose.target + distance * d;
  return pose;
}

double outlineAspect(const Aabb& box, const Vec3& toward_camera, const Vec3& up) {
  const auto [right, image_up] = imageAxes(toward_camera, up);
  double w = 0, h = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 q = corner(box, c) - box.centre();
    w = std::max(w, std::abs(q.dot(right)));
    h = std::max(h, std::abs(q.dot(image_up)));
  }
  return h > 0 ? w / h : 1.0;
}

}  // namespace vdbappear
