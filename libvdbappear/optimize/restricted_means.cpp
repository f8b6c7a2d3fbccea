#include "libvdbappear/optimize/restricted_means.h"

#include "libvdbappear/render/render_image.h"

#include <stdexcept>

namespace vdbappear {

ClusterMasks::ClusterMasks(const RenderResult& coverage)
    : pixels_(coverage.width * coverage.height), clusters_(coverage.cluster_count) {
  if (coverage.cluster_coverage.size() != std::size_t(pixels_) * clusters_)
    throw std::invalid_argument("ClusterMasks: the render has no cluster coverage");
  in_set_.resize(coverage.cluster_coverage.size());
  for (std::size_t i = 0; i < in_set_.size(); ++i) in_set_[i] = coverage.cluster_coverage[i] > 0;
  countPixels();
}

ClusterMasks::ClusterMasks(int pixels, int clusters, std::vector<std::uint8_t> in_set)
    : pixels_(pixels), clusters_(clusters), in_set_(std::move(in_set)) {
  if (in_set_.size() != std::size_t(pixels) * clusters) throw std::invalid_argument("ClusterMasks: wrong size");
  countPixels();
}

void ClusterMasks::restrictToForeground(const std::vector<float>& alpha, double threshold) {
  if (alpha.size() != std::size_t(pixels_)) throw std::invalid_argument("ClusterMasks: alpha has another size");
  for (int p = 0; p < pixels_; ++p)
    if (!(alpha[p] > threshold))
      for (int k = 0; k < clusters_; ++k) in_set_[std::size_t(p) * clusters_ + k] = 0;
  countPixels();
}

void ClusterMasks::countPixels() {
  counts_.assign(clusters_, 0);
  foreground_count_ = 0;
  for (int p = 0; p < pixels_; ++p) {
    for (int k = 0; k < clusters_; ++k) counts_[k] += contains(k, p);
    foreground_count_ += foreground(p);
  }
}

bool ClusterMasks::foreground(int pixel) const {
  for (int k = 0; k < clusters_; ++k)
    if (contains(k, pixel)) return true;
  return false;
}

namespace {

void checkPixels(std::size_t values, std::size_t per_pixel, const ClusterMasks& masks) {
  if (values != std::size_t(masks.pixels()) * per_pixel)
    throw std::invalid_argument("restricted means: image and cluster masks differ in size");
}

}  // namespace

std::vector<Rgb> restrictedMeans(const std::vector<float>& rgb, const ClusterMasks& masks) {
  checkPixels(rgb.size(), 3, masks);
  std::vector<Rgb> mean(masks.clusters(), Rgb::Zero());
  for (int p = 0; p < masks.pixels(); ++p) {
    const Rgb value(rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]);
    for (int k = 0; k < masks.clusters(); ++k)
      if (masks.contains(k, p)) mean[k] += value;
  }
  for (int k = 0; k < masks.clusters(); ++k)
    if (masks.count(k) > 0) mean[k] /= masks.count(k);
  return mean;
}

Rgb foregroundMean(const std::vector<float>& rgb, const ClusterMasks& masks) {
  checkPixels(rgb.size(), 3, masks);
  Rgb sum = Rgb::Zero();
  for (int p = 0; p < masks.pixels(); ++p)
    if (masks.foreground(p)) sum += Rgb(rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]);
  return masks.foregroundCount() > 0 ? Rgb(sum / masks.foregroundCount()) : Rgb(Rgb::Zero());
}

std::vector<Rgb> restrictedGradientMeans(const std::vector<float>& gradients, int parameters,
                                         const ClusterMasks& masks) {
  checkPixels(gradients.size(), 3 * std::size_t(parameters), masks);
  const int K = masks.clusters();
  std::vector<Rgb> mean(std::size_t(K) * parameters, Rgb::Zero());
  for (int p = 0; p < masks.pixels(); ++p) {
    const float* g = &gradients[std::size_t(p) * parameters * 3];
    for (int k = 0; k < K; ++k) {
      if (!masks.contains(k, p)) continue;
      for (int q = 0; q < parameters; ++q) mean[std::size_t(k) * parameters + q] += Rgb(g[3 * q], g[3 * q + 1], g[3 * q + 2]);
    }
  }
  for (int k = 0; k < K; ++k)
    if (masks.count(k) > 0)
      for (int q = 0; q < parameters; ++q) mean[std::size_t(k) * parameters + q] /= masks.count(k);
  return mean;
}

}  // namespace vdbappear
