#pragma once
// Small value types of the library's maths, in double precision.
// Eigen does the linear algebra; these aliases give the code the names of the math.

#include <Eigen/Core>

namespace vdbappear {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Point2 = Eigen::Vector2d;  // a point of [0,1)^2, e.g. two uniform random numbers

}  // namespace vdbappear
