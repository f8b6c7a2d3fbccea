#pragma once
// Restricted mean pixel intensities (§6.3, Eq. 14 and Fig. 8 of the downsampling paper): mean_k(I)
// averages image I over the pixels through which voxels of cluster k are directly visible, so the
// error of each cluster shows apart from the others'. Pixel sets come from the downsampled medium's
// `cluster` AOV (RenderResult::cluster_coverage): cluster k is directly visible in a pixel when some
// camera ray of that pixel has its first real collision in a voxel of cluster k. Light header.

#include "libvdbappear/math/rgb.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

struct RenderResult;

class ClusterMasks {
 public:
  ClusterMasks() = default;
  // From a render with cluster_coverage: pixel p is in set k when its coverage of k is > 0.
  explicit ClusterMasks(const RenderResult& coverage);
  ClusterMasks(int pixels, int clusters, std::vector<std::uint8_t> in_set);  // in_set[p * clusters + k]

  int pixels() const { return pixels_; }
  int clusters() const { return clusters_; }
  bool contains(int k, int pixel) const { return in_set_[std::size_t(pixel) * clusters_ + k] != 0; }
  int count(int k) const { return counts_[k]; }
  // Drops from every set the pixels whose alpha (one value per pixel) is not above `threshold`.
  void restrictToForeground(const std::vector<float>& alpha, double threshold = 0.5);
  // The union of the sets: the pixels where the medium is directly visible (the foreground of mean(I)).
  bool foreground(int pixel) const;
  int foregroundCount() const { return foreground_count_; }

 private:
  void countPixels();
  int pixels_ = 0, clusters_ = 0;
  std::vector<std::uint8_t> in_set_;
  std::vector<int> counts_;
  int foreground_count_ = 0;
};

// mean_k(I) per channel for every k (0 where the set is empty); rgb holds 3 floats per pixel.
std::vector<Rgb> restrictedMeans(const std::vector<float>& rgb, const ClusterMasks& masks);
// mean(I) over the foreground, per channel.
Rgb foregroundMean(const std::vector<float>& rgb, const ClusterMasks& masks);
// mean_k of every gradient image of RenderResult::weight_gradients (parameters per pixel, 3
// channels each): result[k * parameters + p].
std::vector<Rgb> restrictedGradientMeans(const std::vector<float>& gradients, int parameters,
                                         const ClusterMasks& masks);

}  // namespace vdbappear
