#pragma once
// The SGGX normal distribution D (Eq. 4, downsampling paper) sampled on one fixed quadrature of the
// sphere, for the L2 distances between lobes: the fit error behind the lobe count (§5, §8.1) and
// the lobe ordering (Eq. 13, §6.2). Light header: Eigen only.
//
// Quadrature: a spherical Fibonacci set of kNdfQuadraturePoints points on the upper hemisphere,
// equal weights 2 pi / N; the lower hemisphere counts twice that because D(m) = D(-m).

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

inline constexpr int kNdfQuadraturePoints = 2048;

using NdfSamples = std::vector<double>;  // D at the quadrature points

// The quadrature points (z in (0,1], equal areas).
const std::vector<Vec3>& ndfQuadraturePoints();

// D(m) of the SGGX matrix S (SPD) at every quadrature point.
NdfSamples sampleNdf(const Mat3& S);

// integral over the sphere of (a - b)^2.
double sphereL2DistanceSquared(const NdfSamples& a, const NdfSamples& b);

}  // namespace vdbappear
