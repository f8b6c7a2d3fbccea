#pragma once
// Numerical integration over the sphere for tests: (cos theta, phi) cells about a chosen frame,
// each integrated by nested adaptive Gauss-Kronrod (boost::math), so sharp peaks are resolved.

#include "libvdbappear/math/frame.h"

#include <functional>

namespace vdbappear::test {

using SphereFunction = std::function<double(const Vec3&)>;

struct SphereGrid {
  Frame frame = Frame::fromNormal(Vec3(0, 0, 1));  // cos theta is measured along frame.n
  int theta_cells = 32;                             // equal steps in cos theta over [-1, 1]
  int phi_cells = 64;                               // equal steps in phi over [0, 2 pi)
  // Each cell's adaptive quadrature: relative tolerance and depth of bisection. Integrands with
  // kinks off the cell boundaries (max(0, w . m)) need a looser tolerance to finish in seconds.
  double tolerance = 1e-9;
  unsigned max_depth = 12;
};

Vec3 sphericalDirection(const Frame& frame, double cos_theta, double phi);
// The direction at polar angle theta and azimuth phi (degrees) about +z.
Vec3 directionFromDegrees(double theta_degrees, double phi_degrees);

// Integral of f over the cell [c0,c1] x [p0,p1] of (cos theta, phi), to the grid's precision.
double integrateCell(const SphereFunction& f, const SphereGrid& grid, double c0, double c1, double p0, double p1);

// Integral of f over the whole sphere (the sum of all cells of `grid`).
double integrateSphere(const SphereFunction& f, const SphereGrid& grid = {});

}  // namespace vdbappear::test
