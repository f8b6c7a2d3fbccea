#include "libvdbappear/lobes/lobe_fit.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sggx.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

std::array<double, 6> uniqueEntries(const Mat3& S) { return {S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(0, 2), S(1, 2)}; }

WeightedPoints distinctPoints(const std::vector<Mat3>& children) {
  std::vector<std::size_t> order(children.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return uniqueEntries(children[a]) < uniqueEntries(children[b]);
  });
  WeightedPoints points;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Mat3& S = children[order[k]];
    if (k > 0 && uniqueEntries(S) == uniqueEntries(points.S.back())) {
      points.count.back() += 1;
    } else {
      points.S.push_back(S);
      points.count.push_back(1);
    }
  }
  points.total = double(children.size());
  return points;
}

double squaredDistance(const Mat3& a, const Mat3& b) { return (a - b).squaredNorm(); }  // 9-D, Frobenius

int nearestCentre(const Mat3& S, const std::vector<Mat3>& centres) {
  int best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int c = 0; c < int(centres.size()); ++c) {
    const double d2 = squaredDistance(S, centres[c]);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

// k-means++ (Arthur and Vassilvitskii 2007) on weighted points: at most m centres, fewer when every
// remaining point coincides with a centre.
std::vector<Mat3> seedCentres(const WeightedPoints& points, int m, RandomStream& rng) {
  const std::size_t n = points.S.size();
  std::vector<double> d2(n, std::numeric_limits<double>::infinity());
  std::vector<Mat3> centres;
  while (int(centres.size()) < m) {
    std::vector<double> mass(n);
    for (std::size_t k = 0; k < n; ++k) mass[k] = points.count[k] * (centres.empty() ? 1.0 : d2[k]);
    const double total = std::accumulate(mass.begin(), mass.end(), 0.0);
    if (!(total > 0)) break;
    double u = rng.uniform() * total;
    std::size_t pick = 0;
    while (pick + 1 < n && (u -= mass[pick]) >= 0) ++pick;
    while (mass[pick] == 0) --pick;  // rounding at the end of the scan: the last point with mass
    centres.push_back(points.S[pick]);
    for (std::size_t k = 0; k < n; ++k) d2[k] = std::min(d2[k], squaredDistance(points.S[k], centres.back()));
  }
  return centres;
}

// The spherical Fibonacci set on the upper hemisphere (z in (0,1], equal areas).
const std::vector<Vec3>& hemispherePoints() {
  static const std::vector<Vec3> points = [] {
    std::vector<Vec3> p(kLobeErrorPoints);
    const double golden_angle = kPi * (3 - std::sqrt(5.0));
    for (int k = 0; k < kLobeErrorPoints; ++k) {
      const double z = (k + 0.5) / kLobeErrorPoints, r = std::sqrt(std::max(0.0, 1 - z * z));
      p[k] = Vec3(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    }
    return p;
  }();
  return points;
}

// The mean of the children's D at the quadrature points.
std::vector<double> meanD(const WeightedPoints& points) {
  const std::vector<Vec3>& dirs = hemispherePoints();
  std::vector<double> mean(dirs.size(), 0.0);
  for (std::size_t k = 0; k < points.S.size(); ++k) {
    const Sggx sggx(points.S[k]);
    const double w = points.count[k] / points.total;
    for (std::size_t q = 0; q < dirs.size(); ++q) mean[q] += w * sggx.D(dirs[q]);
  }
  return mean;
}

double mixtureError(const std::vector<SggxLobe>& lobes, const std::vector<double>& mean) {
  const std::vector<Vec3>& dirs = hemispherePoints();
  std::vector<Sggx> sggx;
  for (const SggxLobe& lobe : lobes) sggx.emplace_back(lobe.S);
  double sum = 0;
  for (std::size_t q = 0; q < dirs.size(); ++q) {
    double mixture = 0;
    for (std::size_t j = 0; j < lobes.size(); ++j) mixture += lobes[j].fraction * sggx[j].D(dirs[q]);
    sum += (mixture - mean[q]) * (mixture - mean[q]);
  }
  return std::sqrt(2 * (2 * kPi / double(dirs.size())) * sum);  // both hemispheres
}

std::vector<SggxLobe> clusterPoints(const WeightedPoints& points, int m, std::uint64_t seed) {
  RandomStream rng(seed, {m});
  std::vector<Mat3> centres = seedCentres(points, m, rng);
  std::vector<int> cluster(points.S.size(), -1);
  for (int iteration = 0; iteration < 100; ++iteration) {  // Lloyd's iterations
    bool changed = false;
    for (std::size_t k = 0; k < points.S.size(); ++k) {
      const int c = nearestCentre(points.S[k], centres);
      changed |= c != cluster[k];
      cluster[k] = c;
    }
    if (!changed) break;  // (iteration 0 always changes: clusters start at -1)
    std::vector<Mat3> sum(centres.size(), Mat3::Zero());
    std::vector<double> count(centres.size(), 0.0);
    for (std::size_t k = 0; k < points.S.size(); ++k) {
      sum[cluster[k]] += points.count[k] * points.S[k];
      count[cluster[k]] += points.count[k];
    }
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (count[c] > 0) centres[c] = sum[c] / count[c];
  }
  // Eq. (10): each non-empty cluster's mean S, with its share of the children. The centres are
  // those means: every iteration recomputes them from the assignment it made, and the last
  // assignment changed nothing (or was the 100th).
  std::vector<double> count(centres.size(), 0.0);
  for (std::size_t k = 0; k < points.S.size(); ++k) count[cluster[k]] += points.count[k];
  std::vector<SggxLobe> lobes;
  for (std::size_t c = 0; c < centres.size(); ++c)
    if (count[c] > 0) lobes.push_back({centres[c], count[c] / points.total});
  std::stable_sort(lobes.begin(), lobes.end(), [](const SggxLobe& a, const SggxLobe& b) { return a.fraction > b.fraction; });
  return lobes;
}

}  // namespace

double lobeFitError(const std::vector<SggxLobe>& lobes, const std::vector<Mat3>& children) {
  if (children.empty()) throw std::invalid_argument("lobeFitError: no children");
  return mixtureError(lobes, meanD(distinctPoints(children)));
}

std::vector<SggxLobe> clusterLobes(const std::vector<Mat3>& children, int m, std::uint64_t seed) {
  if (children.empty() || m < 1) throw std::invalid_argument("clusterLobes: no children or m < 1");
  return clusterPoints(distinctPoints(children), m, seed);
}

LobeFit fitLobes(const std::vector<Mat3>& children, const LobeFitOptions& options, std::uint64_t seed) {
  if (children.empty()) throw std::invalid_argument("fitLobes: no children");
  const WeightedPoints points = distinctPoints(children);
  const std::vector<double> mean = meanD(points);
  const int most = options.forced_lobes > 0 ? options.forced_lobes : std::max(1, options.max_lobes);
  // Every m up to the cap (for the error report), stopping early once the children run out of
  // distinct S.
  std::vector<std::vector<SggxLobe>> fits;
  LobeFit fit;
  for (int m = 1; m <= most; ++m) {
    fits.push_back(clusterPoints(points, m, seed));
    fit.error_by_lobes.push_back(mixtureError(fits.back(), mean));
    if (int(fits.back().size()) < m) break;
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
