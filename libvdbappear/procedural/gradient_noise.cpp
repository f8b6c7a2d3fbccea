#include "libvdbappear/procedural/gradient_noise.h"

#include "libvdbappear/util/hash_random.h"

#include <cmath>

namespace vdbappear {

namespace {

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

// One of the 12 edge directions of a cube (Perlin 2002), picked by hash.
double gradientDot(std::uint64_t seed, int x, int y, int z, const Vec3& d) {
  static const double kGradients[12][3] = {{1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1}, {-1, 0, 1},
                                           {1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1}};
  const double* g = kGradients[hashKeys(seed, {x, y, z}) % 12];
  return g[0] * d.x() + g[1] * d.y() + g[2] * d.z();
}

}  // namespace

double gradientNoise(const Vec3& p, std::uint64_t seed) {
  const Vec3 floor = p.array().floor();
  const int x = int(floor.x()), y = int(floor.y()), z = int(floor.z());
  const Vec3 f = p - floor;
  const double u = fade(f.x()), v = fade(f.y()), w = fade(f.z());
  double corner[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) corner[i][j][k] = gradientDot(seed, x + i, y + j, z + k, f - Vec3(i, j, k));
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double y0 = lerp(lerp(corner[0][0][0], corner[1][0][0], u), lerp(corner[0][1][0], corner[1][1][0], u), v);
  const double y1 = lerp(lerp(corner[0][0][1], corner[1][0][1], u), lerp(corner[0][1][1], corner[1][1][1], u), v);
  return lerp(y0, y1, w);
}

double fractalNoise(const Vec3& p, std::uint64_t seed, int octaves, double lacunarity, double gain) {
  double sum = 0, norm = 0, amplitude = 1, frequency = 1;
  for (int k = 0; k < octaves; ++k) {
    sum += amplitude * gradientNoise(p * frequency, seed + std::uint64_t(k));
    norm += amplitude;
    amplitude *= gain;
    frequency *= lacunarity;
  }
  return sum / norm;
}

}  // namespace vdbappear
