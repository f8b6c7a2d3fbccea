#pragma once
// Gradient images from the same paths (Appendix A, Eq. 20-24, downsampling paper): the derivative
// of one path's radiance estimate with respect to every lobe-weight scale of a multi-lobe medium,
// carried beside the throughput in forward mode.
//
// Parameter p = k * lobes + j scales the weights of lobe slot j in the voxels of cluster k,
// W_ij -> W_ij (1 + e_p); the derivatives are taken at e_p = 0, so they are d/d(log W) of the lobes
// that parameter scales. The scaled phase function is linear in its weights, f_s = sum_j W_j f_j,
// so d f_s / d e_p = W_j f_j at a vertex of cluster k with a lobe in slot j, and 0 elsewhere
// (Eq. 24: the path's contribution times a sum over its scattering vertices). Extinction, the
// majorant and every sampling decision (free flights, lobe picks, light samples, MIS weights,
// Russian roulette) are held fixed: the estimator is f(x) / pdf(x) with pdf detached, so
// E[(d f / d e) / pdf] = d I / d e wherever pdf > 0, which holds because every lobe with weight
// has pdf > 0 in every direction (SGGX phase functions have full support).
//
// With beta the throughput and dbeta_p its derivative:
//   scattering with f / pdf at a medium vertex:  dbeta_p <- dbeta_p f / pdf + beta (d_p f) / pdf
//   at a surface (no parameter):                 dbeta_p <- dbeta_p f / pdf
//   Russian roulette with survival q:            dbeta_p <- dbeta_p / q
//   light L_w reached through f (NEE):           dL_p += (dbeta_p f + beta d_p f) L_w
//   light L_w reached directly (escape, hit):    dL_p += dbeta_p L_w
// where L_w includes transmittance, MIS weight and 1 / pdf of the light sample. Light header.

#include "libvdbappear/medium/scattering_function.h"

#include <vector>

namespace vdbappear {

class PathGradients {
 public:
  PathGradients(int clusters, int lobes)
      : clusters_(clusters), lobes_(lobes), dbeta_(std::size_t(clusters) * lobes), dL_(dbeta_.size()) {}

  int parameterCount() const { return int(dL_.size()); }
  int lobes() const { return lobes_; }

  void startPath() {
    std::fill(dbeta_.begin(), dbeta_.end(), Rgb(Rgb::Zero()));
    std::fill(dL_.begin(), dL_.end(), Rgb(Rgb::Zero()));
    carrying_ = false;
  }

  // Light through a vertex: the contribution beta * f * light_weight, with per_lobe[j] = W_j f_j
  // (ScatteringFunction::evalLobes) when the vertex is in a medium (fs non-null).
  void addLightThroughVertex(const ScatteringFunction* fs, const Rgb* per_lobe, const Rgb& beta, const Rgb& f,
                             const Rgb& light_weight) {
    if (carrying_)
      for (std::size_t p = 0; p < dL_.size(); ++p) dL_[p] += dbeta_[p] * f * light_weight;
    forEachParameter(fs, [&](int p, int j) { dL_[p] += beta * per_lobe[j] * light_weight; });
  }

  // Light reached directly by the path (escape to the environment, an area light hit).
  void addLight(const Rgb& light_weight) {
    if (!carrying_) return;
    for (std::size_t p = 0; p < dL_.size(); ++p) dL_[p] += dbeta_[p] * light_weight;
  }

  // The path continues from a vertex with weight f / pdf; per_lobe[j] = W_j f_j in the sampled
  // direction (medium vertices) and beta is the throughput before the vertex.
  void scatter(const ScatteringFunction* fs, const Rgb* per_lobe, const Rgb& beta, const Rgb& weight, double pdf) {
    if (carrying_)
      for (Rgb& d : dbeta_) d *= weight;
    forEachParameter(fs, [&](int p, int j) {
      dbeta_[p] += beta * per_lobe[j] / pdf;
      carrying_ = true;
    });
  }

  void scaleThroughput(double factor) {
    if (!carrying_) return;
    for (Rgb& d : dbeta_) d *= factor;
  }

  const std::vector<Rgb>& radianceDerivatives() const { return dL_; }

 private:
  template <typename F>
  void forEachParameter(const ScatteringFunction* fs, F&& f) const {
    if (!fs || fs->cluster() < 0 || fs->cluster() >= clusters_) return;
    for (int j = 0; j < fs->lobeCount(); ++j) {
      const int slot = fs->slot(j);
      if (slot >= 0 && slot < lobes_) f(fs->cluster() * lobes_ + slot, j);
    }
  }

  int clusters_, lobes_;
  std::vector<Rgb> dbeta_, dL_;
  bool carrying_ = false;  // some dbeta_p may be non-zero
};

}  // namespace vdbappear
