#include "libvdbappear/io/medium_summary.h"

#include "libvdbappear/io/medium.h"

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

}  // namespace vdbappear
