#pragma once
// A triangle by its three vertices, counter-clockwise: its normal is (v1 - v0) x (v2 - v0).

#include "libvdbappear/math/vector.h"

#include <array>

namespace vdbappear {

using Triangle = std::array<Vec3, 3>;

}  // namespace vdbappear
