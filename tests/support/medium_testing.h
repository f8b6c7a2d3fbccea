#pragma once
// Helpers for tests that build, write and compare media with OpenVDB directly.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace vdbappear::test {

// The MediumError message of reading `path` with readMedium, or "" when it reads.
std::string readMediumError(const std::string& path, const GridMapping& mapping = {});

// Writes grids and metadata with OpenVDB alone (no validation, no history), as another program might.
void writeRawVdb(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& metadata = {});

// makeRandomMedium with default parameters but for the extent and seed.
MediumPtr randomMedium(int extent, std::uint64_t seed = 1);

// The coloured twill (makeWeave: `resolution` voxels across, `yarns` yarns) reduced by `factor` with
// exactly `lobes` lobes per voxel and `clusters` voxel clusters (downsampleMultiLobe), as
// vdb_lobe_cluster writes it.
MediumPtr multiLobeTwill(int resolution, int yarns, int factor, int lobes, int clusters);

// An empty grid named `name` with the medium's transform, to add as an extra grid.
template <typename GridT = openvdb::FloatGrid>
typename GridT::Ptr namedGridLike(const Medium& medium, const std::string& name,
                                  const typename GridT::ValueType& background = {}) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(medium.transform().copy());
  return grid;
}

// Copies of the medium's voxels (density, albedo, SGGX) at each offset: a medium spread over several
// 128^3 nodes in y and z from a small one.
MediumPtr spreadCopies(const Medium& medium, const std::vector<openvdb::Coord>& offsets);

// A deep copy of every grid of a medium, as a GridPtrVec (for writeRawVdb).
openvdb::GridPtrVec copyGrids(const Medium& medium);

inline double maxAbsDifference(float a, float b) { return std::abs(double(a) - double(b)); }
inline double maxAbsDifference(const openvdb::Vec3s& a, const openvdb::Vec3s& b) {
  return std::max({maxAbsDifference(a[0], b[0]), maxAbsDifference(a[1], b[1]), maxAbsDifference(a[2], b[2])});
}

// Same active topology and, at every active voxel, values within `tolerance` (per component).
template <typename GridT>
::testing::AssertionResult gridsMatch(const GridT& expected, const GridT& actual, double tolerance) {
  if (!expected.tree().hasSameTopology(actual.tree()))
    return ::testing::AssertionFailure() << "grid '" << expected.getName() << "': active topologies differ ("
                                         << expected.activeVoxelCount() << " vs " << actual.activeVoxelCount()
                                         << " active voxels)";
  auto accessor = actual.getConstAccessor();
  for (auto it = expected.cbeginValueOn(); it; ++it) {
    const auto a = *it, b = accessor.getValue(it.getCoord());
    const double difference = maxAbsDifference(a, b);
    if (!(difference <= tolerance))
      return ::testing::AssertionFailure() << "grid '" << expected.getName() << "' at " << it.getCoord() << ": "
                                           << a << " vs " << b;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace vdbappear::test
