#pragma once

#include "libvdbappear/math/vector.h"

namespace vdbappear {

// o + t d, d a unit vector, t in world units.
struct Ray {
  Vec3 o, d;
  Vec3 operator()(double t) const { return o + t * d; }
};

}  // namespace vdbappear
