#pragma once
// Brute-force integration over a planar polygon for tests: int_A f(y) dA by adaptive subdivision of
// triangles (Radon's 7-point degree-5 rule against the sum over four midpoint children), for
// vector-valued f, until every component agrees to `tolerance` (absolute, shared by area).

#include "libvdbappear/math/vector.h"

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace vdbappear::test {

using AreaFunction = std::function<Eigen::VectorXd(const Vec3&)>;

Eigen::VectorXd integratePolygon(const AreaFunction& f, const std::vector<Vec3>& polygon, double tolerance, int size);

}  // namespace vdbappear::test
