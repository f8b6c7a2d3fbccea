#pragma once
// Factors on the lobe weights of a multi-lobe medium, one RGB factor per (voxel cluster k, lobe
// slot j): W_ij -> W_ij * scale(c(i), j). The weight optimisation renders candidate factors this
// way, without rewriting the medium: scale(k, j) = w_kj (Eq. 12, downsampling paper), s_k w_kj
// with colour scales (Eq. 19), or w_kj per channel. Light header.

#include "libvdbappear/medium/scattering_function.h"

#include <stdexcept>
#include <vector>

namespace vdbappear {

class LobeWeightScales {
 public:
  LobeWeightScales() = default;
  LobeWeightScales(int clusters, int lobes)
      : clusters_(clusters), lobes_(lobes), scale_(std::size_t(clusters) * lobes, Rgb::Ones()) {
    if (clusters < 0 || lobes < 0) throw std::invalid_argument("LobeWeightScales: negative size");
  }

  int clusters() const { return clusters_; }
  int lobes() const { return lobes_; }
  Rgb& at(int k, int j) { return scale_[std::size_t(k) * lobes_ + j]; }
  const Rgb& at(int k, int j) const { return scale_[std::size_t(k) * lobes_ + j]; }

  // Scales the lobes of a voxel's scattering function; voxels outside every cluster, and lobes
  // without a slot, keep their weights.
  void apply(ScatteringFunction& f) const {
    const int k = f.cluster();
    if (k < 0 || k >= clusters_) return;
    for (int j = 0; j < f.lobeCount(); ++j)
      if (f.slot(j) >= 0 && f.slot(j) < lobes_) f.scaleWeight(j, at(k, f.slot(j)));
  }

 private:
  int clusters_ = 0, lobes_ = 0;
  std::vector<Rgb> scale_;
};

}  // namespace vdbappear
