#include "libvdbappear/lobes/voxel_clustering.h"

#include "libvdbappear/math/kmeans.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sampling.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>

namespace vdbappear {
namespace {

std::array<double, 3> key(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Vec3 clusteringInput(const Vec3& albedo, std::uint64_t jitter_key, const VoxelClusterOptions& options) {
  if (options.jitter <= 0) return albedo + Vec3::Zero();  // -0 + 0 = +0
  RandomStream rng(options.seed, {std::int64_t(jitter_key)});
  const Point2 a = sampleStandardNormalPair(rng.uniform2()), b = sampleStandardNormalPair(rng.uniform2());
  return albedo + options.jitter * Vec3(a.x(), a.y(), b.x()) + Vec3::Zero();
}

DistinctAlbedoClusters clusterDistinctAlbedos(const std::vector<Vec3>& albedo, const std::vector<double>& count,
                                              const VoxelClusterOptions& options) {
  if (options.clusters < 1) throw std::invalid_argument("clusterDistinctAlbedos: K < 1");
  DistinctAlbedoClusters result;
  if (albedo.empty()) return result;
  RandomStream rng(options.seed, {-1});
  const KMeansResult<Vec3> clusters = kMeans(albedo, count, options.clusters, rng);

  // Label the clusters by increasing albedo (channel sum, then channels), whatever K-means' order.
  std::vector<int> order(clusters.centres.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Vec3 &ca = clusters.centres[a], &cb = clusters.centres[b];
    return std::make_pair(ca.sum(), key(ca)) < std::make_pair(cb.sum(), key(cb));
  });
  std::vector<int> label(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    label[order[k]] = int(k);
    result.centres.push_back(clusters.centres[order[k]]);
  }
  result.label.resize(albedo.size());
  for (std::size_t i = 0; i < albedo.size(); ++i) result.label[i] = label[clusters.cluster[i]];
  return result;
}

VoxelClustering clusterVoxels(const std::vector<Vec3>& albedo, const std::vector<std::uint64_t>& jitter_key,
                              const VoxelClusterOptions& options) {
  if (options.clusters < 1) throw std::invalid_argument("clusterVoxels: K < 1");
  if (jitter_key.size() != albedo.size()) throw std::invalid_argument("clusterVoxels: one jitter key per voxel");
  std::vector<Vec3> input(albedo.size());
  for (std::size_t i = 0; i < albedo.size(); ++i) input[i] = clusteringInput(albedo[i], jitter_key[i], options);
  const DistinctPoints<Vec3> distinct = distinctPoints(input);

  VoxelClustering result;
  result.distinct_albedos = distinct.point.size();
  DistinctAlbedoClusters clusters = clusterDistinctAlbedos(distinct.point, distinct.count, options);
  result.centres = std::move(clusters.centres);
  result.cluster.resize(albedo.size());
  for (std::size_t i = 0; i < albedo.size(); ++i) result.cluster[i] = clusters.label[distinct.of[i]];
  return result;
}

}  // namespace vdbappear
