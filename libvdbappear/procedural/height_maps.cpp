#include "libvdbappear/procedural/height_maps.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/smoothstep.h"
#include "libvdbappear/procedural/weave_pattern.h"
#include "libvdbappear/util/hash_random.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace vdbappear {
namespace {

HeightField sampled(int cells, const std::function<double(double x, double y)>& h) {
  if (cells < 1) throw std::invalid_argument("a height map needs at least one cell");
  HeightField field(cells, cells, 1.0 / cells);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) field.at(i, j) = h(double(i) / cells, double(j) / cells);
  return field;
}

double positiveModulo(double x, double period) { return x - period * std::floor(x / period); }

// A yarn's centre height at position t along it (in yarn spacings), given the heights at the
// crossings k + 0.5 by `crossing(k)`: smoothstep between the two nearest crossings.
double centreLine(double t, const std::function<double(int)>& crossing) {
  const double c = t - 0.5;
  const int k = int(std::floor(c));
  return crossing(k) + (crossing(k + 1) - crossing(k)) * smoothstep(c - k);
}

}  // namespace

HeightField wovenHeightMap(int cells, const WeavePattern& pattern, int yarns) {
  if (yarns < 1 || cells % yarns != 0) throw std::invalid_argument("wovenHeightMap: cells must be a multiple of yarns");
  if (yarns % pattern.repeat() != 0) throw std::invalid_argument("wovenHeightMap: yarns must be a multiple of the weave's repeat");
  const double half_width = 0.45, bulge = 0.3, undulation = 0.15;  // in yarn spacings
  return sampled(cells, [&](double x, double y) {
    const double gx = x * yarns, gy = y * yarns;  // in yarn spacings
    const int warp = int(std::floor(gx)) % yarns, weft = int(std::floor(gy)) % yarns;
    const double across_warp = (positiveModulo(gx, 1) - 0.5) / half_width;  // -1..1 over the warp's width
    const double across_weft = (positiveModulo(gy, 1) - 0.5) / half_width;
    double h = -undulation - 0.2 * bulge;  // the gaps between yarns
    if (std::abs(across_warp) <= 1) {
      const double centre = centreLine(gy, [&](int k) { return pattern.warpOver(warp, k) ? undulation : -undulation; });
      h = std::max(h, centre + bulge * (1 - across_warp * across_warp));
    }
    if (std::abs(across_weft) <= 1) {
      const double centre = centreLine(gx, [&](int k) { return pattern.warpOver(k, weft) ? -undulation : undulation; });
      h = std::max(h, centre + bulge * (1 - across_weft * across_weft));
    }
    return h / yarns;  // in map widths
  });
}

HeightField noiseHeightMap(int cells, std::uint64_t seed) {
  struct Wave {
    double a, b, phase, amplitude;
  };
  std::vector<Wave> waves;
  double slope_square = 0;
  for (int k = 0; k < 48; ++k) {
    const double f = 4 * std::pow(16.0, hashUniform(seed, {k, 0}));  // 4 to 64 cycles per map
    const double angle = 2 * kPi * hashUniform(seed, {k, 1});
    const double a = std::round(f * std::cos(angle)), b = std::round(f * std::sin(angle));  // whole cycles: tiles
    const double frequency = std::hypot(a, b);
    if (frequency == 0) continue;
    waves.push_back({a, b, 2 * kPi * hashUniform(seed, {k, 2}), 1 / frequency});
    slope_square += 0.5 * std::pow(2 * kPi, 2);  // the mean of |grad|^2 of (1 / f) sin(2 pi f x)
  }
  const double scale = 0.6 / std::sqrt(slope_square);
  return sampled(cells, [&](double x, double y) {
    double h = 0;
    for (const Wave& w : waves) h += w.amplitude * std::sin(2 * kPi * (w.a * x + w.b * y) + w.phase);
    return scale * h;
  });
}

HeightField reliefHeightMap(int cells) {
  const double tiles = 8, height = 0.2, chamfer = 0.08, ring = 0.22, ring_width = 0.04, groove = 0.06;
  return sampled(cells, [&](double x, double y) {
    const double u = positiveModulo(x * tiles, 1) - 0.5, v = positiveModulo(y * tiles, 1) - 0.5;  // -0.5..0.5
    const double square = std::max(std::abs(u), std::abs(v));
    double h = height * smoothstep((0.4 - square) / chamfer);  // raised square, chamfered edges
    const double r = std::hypot(u, v);
    h -= groove * smoothstep(1 - std::abs(r - ring) / ring_width);  // engraved ring
    return h / tiles;
  });
}

HeightField bumpsHeightMap(int cells, std::uint64_t seed) {
  const int lattice = 8;
  const double flattening = 0.6;
  return sampled(cells, [&](double x, double y) {
    const int a = int(std::floor(positiveModulo(x * lattice, lattice))), b = int(std::floor(positiveModulo(y * lattice, lattice)));
    const double radius = 0.3 + 0.15 * hashUniform(seed, {a, b, 0});
    const double cx = a + 0.5 + 0.1 * (hashUniform(seed, {a, b, 1}) - 0.5), cy = b + 0.5 + 0.1 * (hashUniform(seed, {a, b, 2}) - 0.5);
    const double d2 = std::pow(positiveModulo(x * lattice, lattice) - cx, 2) + std::pow(positiveModulo(y * lattice, lattice) - cy, 2);
    return d2 < radius * radius ? flattening * std::sqrt(radius * radius - d2) / lattice : 0.0;
  });
}

const std::vector<std::string>& heightMapNames() {
  static const std::vector<std::string> names{"woven", "noise", "relief", "bumps"};
  return names;
}

HeightField heightMapByName(const std::string& name, int cells, std::uint64_t seed) {
  if (name == "woven") return wovenHeightMap(cells, WeavePattern::twill(4), 16);
  if (name == "noise") return noiseHeightMap(cells, seed);
  if (name == "relief") return reliefHeightMap(cells);
  if (name == "bumps") return bumpsHeightMap(cells, seed);
  throw std::invalid_argument("unknown height map '" + name + "' (woven, noise, relief, bumps)");
}

}  // namespace vdbappear
