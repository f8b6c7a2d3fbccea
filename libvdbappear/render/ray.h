#pragma once

#include "libvdbappear/math/vector.h"

namespace vdbappear {

// o + t d, d a unit vector, t in world units. Camera rays also carry their pixel's angular width
// (the square root of its solid angle, radians), from which a mipmap's level of detail is chosen
// (render/level_of_detail.h); 0 for every other ray.
struct Ray {
  Vec3 o, d;
  double spread = 0;
  Vec3 operator()(double t) const { return o + t * d; }
};

}  // namespace vdbappear
