#include "libvdbappear/io/medium_summary.h"

#include "libvdbappear/io/medium.h"

#include <algorithm>

namespace vdbappear {

MediumSummary summarize(const Medium& medium) {
  MediumSummary summary;
  for (const auto& grid : medium.grids()) {
    GridSummary g{grid->getName(), grid->valueType(), grid->activeVoxelCount(), grid->memUsage()};
    summary.memory_bytes += g.memory_bytes;
    summary.grids.push_back(std::move(g));
  }
  summary.active_voxels = medium.density->activeVoxelCount();
  summary.voxel_size = medium.transform().voxelSize()[0];
  return summary;
}

void addSummary(MediumSummary& whole, const MediumSummary& part) {
  whole.active_voxels += part.active_voxels;
  whole.memory_bytes += part.memory_bytes;
  whole.voxel_size = part.voxel_size;
  for (const GridSummary& g : part.grids) {
    auto it = std::find_if(whole.grids.begin(), whole.grids.end(), [&](const GridSummary& t) { return t.name == g.name; });
    if (it == whole.grids.end()) {
      whole.grids.push_back(g);
    } else {
      it->active_voxels += g.active_voxels;
      it->memory_bytes += g.memory_bytes;
    }
  }
}

}  // namespace vdbappear
