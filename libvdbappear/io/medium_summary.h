#pragma once
// How a medium is made up (grids, voxel counts, bytes), for reports. Light header.

#include <cstdint>
#include <string>
#include <vector>

namespace vdbappear {

struct Medium;

struct GridSummary {
  std::string name;
  std::string type;
  std::uint64_t active_voxels = 0;
  std::uint64_t memory_bytes = 0;
};

struct MediumSummary {
  std::vector<GridSummary> grids;
  std::uint64_t active_voxels = 0;  // of the density grid
  std::uint64_t memory_bytes = 0;   // all grids, in memory
  double voxel_size = 0;            // world units, along x
};

MediumSummary summarize(const Medium& medium);

// Adds a part's summary to the whole's (parts share no voxel): grids by name, counts and bytes summed.
void addSummary(MediumSummary& whole, const MediumSummary& part);

}  // namespace vdbappear
