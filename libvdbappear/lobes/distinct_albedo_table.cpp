#include "libvdbappear/lobes/distinct_albedo_table.h"

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

namespace {

bool lexicographicLess(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

}  // namespace

void DistinctAlbedoTable::add(std::vector<Vec3>& albedos) {
  std::sort(albedos.begin(), albedos.end(), lexicographicLess);
  // The part's distinct albedos and counts, then merged into the table from the back, in place: the
  // table grows by at most the part's size, never to a copy of itself beside it.
  std::vector<Vec3> part;
  std::vector<double> part_voxels;
  for (const Vec3& a : albedos) {
    if (part.empty() || lexicographicLess(part.back(), a)) {
      part.push_back(a);
      part_voxels.push_back(0);
    }
    part_voxels.back() += 1;
  }
  const std::size_t n = albedo_.size(), m = part.size();
  if (albedo_.capacity() < n + m) {  // grow by an eighth, not double: the table is the largest thing kept
    albedo_.reserve(n + m + (n + m) / 8);
    voxels_.reserve(n + m + (n + m) / 8);
  }
  albedo_.resize(n + m);
  voxels_.resize(n + m);
  std::size_t i = n, j = m, k = n + m;  // next from the table, next from the part, next place written
  while (j > 0) {
    --k;
    if (i > 0 && lexicographicLess(part[j - 1], albedo_[i - 1])) {
      --i;
      albedo_[k] = albedo_[i];
      voxels_[k] = voxels_[i];
    } else if (i > 0 && !lexicographicLess(albedo_[i - 1], part[j - 1])) {  // the same albedo
      --i, --j;
      albedo_[k] = albedo_[i];
      voxels_[k] = voxels_[i] + part_voxels[j];
    } else {
      --j;
      albedo_[k] = part[j];
      voxels_[k] = part_voxels[j];
    }
  }
  // The table's first i entries are in place; the merged ones start at k >= i (> where albedos met).
  albedo_.erase(albedo_.begin() + std::ptrdiff_t(i), albedo_.begin() + std::ptrdiff_t(k));
  voxels_.erase(voxels_.begin() + std::ptrdiff_t(i), voxels_.begin() + std::ptrdiff_t(k));
}

std::size_t DistinctAlbedoTable::find(const Vec3& albedo) const {
  const auto entry = std::lower_bound(albedo_.begin(), albedo_.end(), albedo, lexicographicLess);
  if (entry == albedo_.end() || lexicographicLess(albedo, *entry))
    throw std::logic_error("voxel clustering: an albedo that the table of the medium's parts does not hold");
  return std::size_t(entry - albedo_.begin());
}

}  // namespace vdbappear
