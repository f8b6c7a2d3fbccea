#pragma once
// Linear RGB triples (radiance, albedo, path throughput): element-wise arithmetic through Eigen.

#include <Eigen/Core>

namespace vdbappear {

using Rgb = Eigen::Array3d;

inline double average(const Rgb& c) { return c.sum() / 3; }

}  // namespace vdbappear
