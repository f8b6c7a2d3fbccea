#pragma once
// Random symmetric positive definite matrices, for tests and procedural media.

#include "libvdbappear/math/vector.h"

#include <Eigen/Geometry>

#include <cmath>

namespace vdbappear {

// A uniformly distributed rotation from three uniform numbers (Shoemake 1992, "Uniform random
// rotations").
inline Mat3 uniformRotation(double u1, double u2, double u3) {
  constexpr double kTwoPi = 6.283185307179586;
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const Eigen::Quaterniond q(b * std::cos(kTwoPi * u3), a * std::sin(kTwoPi * u2), a * std::cos(kTwoPi * u2),
                             b * std::sin(kTwoPi * u3));
  return q.toRotationMatrix();
}

// R diag(lambda) R^T with R uniform and eigenvalues log-uniform in [min_eigenvalue, 1]
// (u_eigen in [0,1)^3 picks them). min_eigenvalue must be > 0.
inline Mat3 randomSpdMatrix(double u1, double u2, double u3, const Vec3& u_eigen, double min_eigenvalue) {
  const Mat3 R = uniformRotation(u1, u2, u3);
  Vec3 lambda;
  for (int k = 0; k < 3; ++k) lambda[k] = std::pow(min_eigenvalue, u_eigen[k]);
  return R * lambda.asDiagonal() * R.transpose();
}

}  // namespace vdbappear
