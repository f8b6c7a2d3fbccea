#pragma once
// The input of voxel clustering (§6.2 of the downsampling paper) gathered over parts of a medium:
// the distinct (jittered) coarse albedos, sorted lexicographically, each with the number of voxels
// that hold it. K-means on the table (clusterDistinctAlbedos) gives the clusters of the whole medium
// whatever the parts and their order; a voxel's cluster is that of its albedo's entry. 32 bytes a
// distinct albedo. Light header: Eigen only.

#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

class DistinctAlbedoTable {
 public:
  // Adds one part's voxels, one albedo each, in any order (the vector is sorted in place).
  void add(std::vector<Vec3>& albedos);

  // The entry of an albedo the table holds; std::logic_error if it holds none.
  std::size_t find(const Vec3& albedo) const;

  const std::vector<Vec3>& albedo() const { return albedo_; }
  const std::vector<double>& voxels() const { return voxels_; }
  std::size_t size() const { return albedo_.size(); }
  std::uint64_t bytes() const { return albedo_.capacity() * sizeof(Vec3) + voxels_.capacity() * sizeof(double); }

 private:
  std::vector<Vec3> albedo_;  // sorted, no albedo twice
  std::vector<double> voxels_;
};

}  // namespace vdbappear
