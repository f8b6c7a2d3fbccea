#pragma once
// A rigid motion p -> rotation p + offset (rotation orthonormal with determinant +1): where a copy
// of a mesh lies, e.g. a plane's tiles (translations) or a sphere's tiles along one latitude band
// (turns about its axis, surface/sphere_shell.h).

#include "libvdbappear/math/vector.h"

namespace vdbappear {

struct RigidMotion {
  Mat3 rotation = Mat3::Identity();
  Vec3 offset = Vec3::Zero();

  static RigidMotion translation(const Vec3& offset) { return {Mat3::Identity(), offset}; }
  Vec3 operator()(const Vec3& p) const { return rotation * p + offset; }
  Vec3 direction(const Vec3& d) const { return rotation * d; }
};

}  // namespace vdbappear
