#pragma once
// Gradient noise (Perlin 2002, "Improving Noise": quintic fade, gradients at lattice points) and
// its fractal sum. Gradients come from a counter-based hash of the lattice point and the seed, so
// the noise needs no tables and is the same on every thread.

#include "libvdbappear/math/vector.h"

#include <cstdint>

namespace vdbappear {

// In roughly [-1,1], 0 at lattice points, smooth (C2).
double gradientNoise(const Vec3& p, std::uint64_t seed);

// sum_k gain^k noise(lacunarity^k p), k < octaves, divided by sum_k gain^k.
double fractalNoise(const Vec3& p, std::uint64_t seed, int octaves, double lacunarity = 2, double gain = 0.5);

}  // namespace vdbappear
