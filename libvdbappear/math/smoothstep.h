#pragma once
// The cubic Hermite step 3t^2 - 2t^3 of t clamped to [0,1]: 0 below, 1 above, C1 in between.

#include <algorithm>

namespace vdbappear {

inline double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

}  // namespace vdbappear
