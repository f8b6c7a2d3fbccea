#pragma once
// Exemplar blocks for the modularity tool (§7, downsampling paper): N woven blocks of equal size,
// each a variant of weave pattern and yarn colours, side by side along x in one medium, plus the
// `exemplar_layout` grid (docs/medium.md) that places exemplars on a W x H sheet of blocks (a synthesized model).
// Every block holds whole pattern repeats, so each one tiles seamlessly with itself.

#include "libvdbappear/io/medium_file.h"

#include <cstdint>
#include <string>

namespace vdbappear {

struct ExemplarParams {
  int resolution = 64;        // voxels along a block's side (x and y)
  std::uint64_t seed = 1;
  int count = 6;              // N exemplars
  int block_yarns = 4;        // yarns per block side; a multiple of 4 holds whole repeats of every variant
  int layout_width = 8;       // blocks of the synthesized sheet along x ...
  int layout_height = 8;      // ... and y
  double fiber_density = 40;
  double roughness = 0.1;
};

MediumPtr makeExemplars(const ExemplarParams& params);

}  // namespace vdbappear
