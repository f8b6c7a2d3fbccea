#pragma once
// The unknowns of the weight optimisation (§6.1, §6.4 of the downsampling paper): one factor w_kj
// per voxel cluster k and lobe slot j, scaling the naive lobe weights (Eq. 12)
//   W_ij = W_ij^naive w_c(i)j,
// optionally with a colour scale s_k per cluster (Eq. 19, semi-coloured media)
//   W_ij^c = s_c(i)^c W_ij^naive,c w_c(i)j,
// or with w_kj per channel instead (--per-channel, the comparison of Fig. 15).
//
// Gradients arrive as derivatives with respect to the log of each lobe's scale per channel,
// d/de_kj^c with scale_kj^c = s_k^c w_kj^c = exp(e_kj^c) (render/path_gradients.h), and map to the
// factors by the chain rule: d/dw_kj = sum_c d/de_kj^c / w_kj, d/ds_k^c = sum_j d/de_kj^c / s_k^c,
// per channel d/dw_kj^c = d/de_kj^c / w_kj^c. Light header.

#include "libvdbappear/medium/lobe_weight_scales.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace vdbappear {

enum class ColourMode {
  kGrey,          // w_kj only (Eq. 12)
  kColourScales,  // w_kj and s_k (Eq. 19)
  kPerChannel,    // w_kj per RGB channel
};
const char* colourModeName(ColourMode mode);  // "grey", "colour-scales", "per-channel"
ColourMode parseColourMode(const std::string& name);  // throws std::invalid_argument

class WeightFactors {
 public:
  WeightFactors() = default;
  WeightFactors(int clusters, int lobes, ColourMode mode);  // w = 1, s = 1 (the paper's w^(0))

  int clusters() const { return clusters_; }
  int lobes() const { return lobes_; }
  ColourMode mode() const { return mode_; }

  // w_kj (grey and colour-scale modes: the same value in every channel) and s_k.
  const Rgb& w(int k, int j) const { return w_[std::size_t(k) * lobes_ + j]; }
  const Rgb& s(int k) const { return s_[k]; }
  Rgb& w(int k, int j) { return w_[std::size_t(k) * lobes_ + j]; }
  Rgb& s(int k) { return s_[k]; }

  // The scale of every (cluster, slot): s_k w_kj per channel.
  LobeWeightScales scales() const;

  // The free parameters as one vector, in this order: per cluster k, w_k0 .. w_k(m-1) (per channel:
  // R, G, B of each), then (colour scales) s_k^R, s_k^G, s_k^B.
  int parameterCount() const;
  std::vector<double> parameters() const;
  void setParameters(const std::vector<double>& theta);
  std::vector<std::string> parameterNames() const;  // "w_0,1", "s_0.G", "w_1,0.R"

  // Chain rule: from dX/de_kj^c (per (k, j) an RGB, index k * lobes + j) to dX/dtheta. With colour
  // scales, the w_k part is projected onto the tangent of the gauge below, sum_j dw_kj / w_kj = 0.
  // gauge = false: without that projection (the effect of each parameter alone).
  std::vector<double> chainRule(const std::vector<Rgb>& d_log_scale, bool gauge = true) const;

  // The gauge of colour scales: s_k w_kj is all that renders, so one factor per cluster is free.
  // w_k is rescaled to a geometric mean of 1 over its lobes and s_k takes the difference: s_k is the
  // cluster's brightness per channel, w_k the balance of its lobes. (The other gauge, a channel mean
  // of 1 for s_k, makes w_k and s_k^R nearly the same parameter on a red medium: on the red velvet
  // its Gauss-Newton matrix had a direction of relative curvature 0.015, which took the first step
  // to w = 1.5 and E from 0.15 to 0.60.) With one lobe, w = 1 and s_k is a factor per channel.
  void normaliseColourScales();

  // The JSON of the file metadata `weight_factors` (docs/medium.md §5): {"clusters", "lobes",
  // "mode", "w": [[per lobe: RGB]] per cluster, "s": [RGB per cluster]}.
  nlohmann::json toJson() const;
  static WeightFactors fromJson(const nlohmann::json& json);  // throws std::invalid_argument

 private:
  int clusters_ = 0, lobes_ = 0;
  ColourMode mode_ = ColourMode::kGrey;
  std::vector<Rgb> w_;  // [k * lobes + j]
  std::vector<Rgb> s_;  // [k]
};

}  // namespace vdbappear
