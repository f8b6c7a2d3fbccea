#include "sphere_quadrature.h"

#include "libvdbappear/math/constants.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <cmath>

namespace vdbappear::test {

Vec3 sphericalDirection(const Frame& frame, double cos_theta, double phi) {
  const double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  return frame.toWorld(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
}

Vec3 directionFromDegrees(double theta_degrees, double phi_degrees) {
  return sphericalDirection(Frame::fromNormal(Vec3(0, 0, 1)), std::cos(theta_degrees * kPi / 180), phi_degrees * kPi / 180);
}

double integrateCell(const SphereFunction& f, const SphereGrid& grid, double c0, double c1, double p0, double p1) {
  using Rule = boost::math::quadrature::gauss_kronrod<double, 15>;
  auto over_phi = [&](double cos_theta) {
    return Rule::integrate([&](double phi) { return f(sphericalDirection(grid.frame, cos_theta, phi)); }, p0, p1,
                           grid.max_depth, grid.tolerance);
  };
  return Rule::integrate(over_phi, c0, c1, grid.max_depth, grid.tolerance);
}

double integrateSphere(const SphereFunction& f, const SphereGrid& grid) {
  double sum = 0;
  for (int i = 0; i < grid.theta_cells; ++i) {
    const double c0 = -1 + 2.0 * i / grid.theta_cells, c1 = -1 + 2.0 * (i + 1) / grid.theta_cells;
    for (int j = 0; j < grid.phi_cells; ++j) {
      const double p0 = 2 * kPi * j / grid.phi_cells, p1 = 2 * kPi * (j + 1) / grid.phi_cells;
      sum += integrateCell(f, grid, c0, c1, p0, p1);
    }
  }
  return sum;
}

}  // namespace vdbappear::test
