#include "libvdbappear/lobes/lobe_fit.h"

#include "libvdbappear/lobes/ndf_quadrature.h"
#include "libvdbappear/math/kmeans.h"
#include "libvdbappear/math/random_stream.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace vdbappear {
namespace {

// The children as distinct S with multiplicities: voxels of one fibre often share their S.
struct WeightedPoints {
  std::vector<Mat3> S;
  std::vector<double> count;
  double total = 0;
};

WeightedPoints distinctChildren(const std::vector<Mat3>& children) {
  DistinctPoints<Mat3> distinct = distinctPoints(children);
  return {std::move(distinct.point), std::move(distinct.count), double(children.size())};
}

// The mean of the children's D at the quadrature points.
NdfSamples meanNdf(const WeightedPoints& points) {
  NdfSamples mean(kNdfQuadraturePoints, 0.0);
  for (std::size_t k = 0; k < points.S.size(); ++k) {
    const NdfSamples D = sampleNdf(points.S[k]);
    const double w = points.count[k] / points.total;
    for (std::size_t q = 0; q < D.size(); ++q) mean[q] += w * D[q];
  }
  return mean;
}

double mixtureError(const std::vector<SggxLobe>& lobes, const NdfSamples& mean) {
  NdfSamples mixture(mean.size(), 0.0);
  for (const SggxLobe& lobe : lobes) {
    const NdfSamples D = sampleNdf(lobe.S);
    for (std::size_t q = 0; q < D.size(); ++q) mixture[q] += lobe.fraction * D[q];
  }
  return std::sqrt(sphereL2DistanceSquared(mixture, mean));
}

// Eq. (10): each cluster's mean S (the K-means centre), with its share of the children.
std::vector<SggxLobe> clusterPoints(const WeightedPoints& points, int m, std::uint64_t seed) {
  RandomStream rng(seed, {m});
  const KMeansResult<Mat3> clusters = kMeans(points.S, points.count, m, rng);
  std::vector<SggxLobe> lobes;
  for (std::size_t c = 0; c < clusters.centres.size(); ++c)
    lobes.push_back({clusters.centres[c], clusters.weight[c] / points.total});
  std::stable_sort(lobes.begin(), lobes.end(), [](const SggxLobe& a, const SggxLobe& b) { return a.fraction > b.fraction; });
  return lobes;
}

}  // namespace

double lobeFitError(const std::vector<SggxLobe>& lobes, const std::vector<Mat3>& children) {
  if (children.empty()) throw std::invalid_argument("lobeFitError: no children");
  return mixtureError(lobes, meanNdf(distinctChildren(children)));
}

LobeFit fitLobes(const std::vector<Mat3>& children, const LobeFitOptions& options, std::uint64_t seed) {
  if (children.empty()) throw std::invalid_argument("fitLobes: no children");
  const WeightedPoints points = distinctChildren(children);
  const NdfSamples mean = meanNdf(points);
  const int most = options.forced_lobes > 0 ? options.forced_lobes : std::max(1, options.max_lobes);
  // Every m up to the cap (for the error report), stopping early once every distinct S is a lobe
  // of its own (an exact fit: more lobes cannot help).
  std::vector<std::vector<SggxLobe>> fits;
  LobeFit fit;
  fit.target_norm = std::sqrt(sphereL2DistanceSquared(mean, NdfSamples(mean.size(), 0.0)));
  for (int m = 1; m <= most; ++m) {
    fits.push_back(clusterPoints(points, m, seed));
    fit.error_by_lobes.push_back(mixtureError(fits.back(), mean));
    if (fits.back().size() == points.S.size()) break;
  }
  std::size_t chosen = fits.size() - 1;  // forced: the largest m fitted
  if (options.forced_lobes <= 0) {       // §8.1: add a lobe while it at least halves the error
    chosen = 0;
    while (chosen + 1 < fits.size() && fits[chosen + 1].size() > fits[chosen].size() &&
           fit.error_by_lobes[chosen + 1] <= options.keep_ratio * fit.error_by_lobes[chosen])
      ++chosen;
  }
  fit.lobes = fits[chosen];
  return fit;
}

}  // namespace vdbappear
