#pragma once
// Procedural height fields for the displacement tests: sums of sinusoids with random directions and
// phases, one per period.

#include "libvdbappear/math/constants.h"
#include "libvdbappear/surface/height_field.h"

#include "test_random.h"

#include <cmath>
#include <vector>

namespace vdbappear::test {

// cells x cells cells of side cell_size; a wave of period P cells has amplitude
// amplitude_per_period * P (so every wave's slopes peak at 2 pi amplitude_per_period / cell_size).
inline HeightField sinusoidHeightField(int cells, double cell_size, const std::vector<double>& periods,
                                       double amplitude_per_period, std::uint64_t seed) {
  TestRandom random(seed);
  struct Wave {
    double kx, ky, phase, amplitude;
  };
  std::vector<Wave> waves;
  for (double period : periods) {
    const double angle = 2 * kPi * random.uniform(), k = 2 * kPi / (period * cell_size);
    const double phase = 2 * kPi * random.uniform();
    waves.push_back({k * std::cos(angle), k * std::sin(angle), phase, amplitude_per_period * period});
  }
  HeightField field(cells, cells, cell_size);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      double h = 0;
      for (const Wave& w : waves) h += w.amplitude * std::sin(w.kx * i * cell_size + w.ky * j * cell_size + w.phase);
      field.at(i, j) = h;
    }
  return field;
}

// The same over a map that tiles seamlessly: each wave of period about P cells turned to the
// nearest whole numbers of cycles (a, b) across the map (not both 0), so opposite edges match.
inline HeightField periodicHeightField(int cells, double cell_size, const std::vector<double>& periods,
                                       double amplitude_per_period, std::uint64_t seed) {
  TestRandom random(seed);
  struct Wave {
    int a, b;
    double phase, amplitude;
  };
  std::vector<Wave> waves;
  for (double period : periods) {
    const double angle = 2 * kPi * random.uniform(), cycles = cells / period;
    Wave w{int(std::lround(cycles * std::cos(angle))), int(std::lround(cycles * std::sin(angle))), 2 * kPi * random.uniform(),
           amplitude_per_period * period};
    if (w.a == 0 && w.b == 0) w.a = 1;
    waves.push_back(w);
  }
  HeightField field(cells, cells, cell_size);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      double h = 0;
      for (const Wave& w : waves) h += w.amplitude * std::sin(2 * kPi * double(w.a * i + w.b * j) / cells + w.phase);
      field.at(i, j) = h;
    }
  return field;
}

}  // namespace vdbappear::test
