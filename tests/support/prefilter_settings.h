#pragma once
// Prefiltering settings small enough for unit tests (prefilter/displacement_prefilter.h): factor 8,
// 64 paths per estimate, T of 2 x 2 bins and S of 3^2 x 3^2, few pairs and positions.

#include "libvdbappear/prefilter/displacement_prefilter.h"

namespace vdbappear::test {

inline DisplacementPrefilterSettings smallPrefilterSettings() {
  DisplacementPrefilterSettings s;
  s.factor = 8;
  s.samples_per_side = 8;
  s.factorization.spatial_resolution = 2;
  s.factorization.angular_resolution = 3;
  s.factorization.pairs_per_spatial_bin = 20;
  s.factorization.positions_per_angular_bin = 4;
  return s;
}

}  // namespace vdbappear::test
