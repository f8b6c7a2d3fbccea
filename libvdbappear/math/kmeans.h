#pragma once
// Weighted K-means: k-means++ seeding (Arthur and Vassilvitskii 2007) then Lloyd iterations, on
// Eigen points with the Euclidean distance (Vec3 albedos; Mat3 SGGX matrices, read as 9-D vectors
// with the Frobenius distance). Deterministic: every random choice comes from the caller's stream.
// Light header: Eigen only.

#include "libvdbappear/math/random_stream.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace vdbappear {

template <class Point>
struct KMeansResult {
  std::vector<Point> centres;   // each cluster's weighted mean; no cluster is empty
  std::vector<double> weight;   // each cluster's total weight
  std::vector<int> cluster;     // the cluster of each point
};

// Equal points merged into one with a count, sorted by their coefficients (so the result does not
// depend on the order of the input); of[i] is the distinct point that input i became.
template <class Point>
struct DistinctPoints {
  std::vector<Point> point;
  std::vector<double> count;
  std::vector<int> of;
};

template <class Point>
DistinctPoints<Point> distinctPoints(const std::vector<Point>& points) {
  auto less = [](const Point& a, const Point& b) {
    return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(), b.data() + b.size());
  };
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return less(points[a], points[b]); });
  DistinctPoints<Point> d;
  d.of.resize(points.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Point& p = points[order[k]];
    if (k == 0 || less(d.point.back(), p)) {
      d.point.push_back(p);
      d.count.push_back(0);
    }
    d.count.back() += 1;
    d.of[order[k]] = int(d.point.size()) - 1;
  }
  return d;
}

namespace kmeans_detail {

template <class Point>
int nearestCentre(const Point& p, const std::vector<Point>& centres) {
  int best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int c = 0; c < int(centres.size()); ++c) {
    const double d2 = (p - centres[c]).squaredNorm();
    if (d2 < best_d2) {  // ties: the lower index
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

// k-means++: the first centre is drawn with probability proportional to weight, each next one
// proportional to weight * (squared distance to the nearest centre so far). Stops early when every
// point coincides with a centre, so the centres are distinct points.
template <class Point>
std::vector<Point> seedCentres(const std::vector<Point>& points, const std::vector<double>& weights, int k,
                               RandomStream& rng) {
  const std::size_t n = points.size();
  std::vector<double> d2(n, 1.0), mass(n);
  std::vector<Point> centres;
  while (int(centres.size()) < k) {
    for (std::size_t i = 0; i < n; ++i) mass[i] = weights[i] * d2[i];
    const double total = std::accumulate(mass.begin(), mass.end(), 0.0);
    if (!(total > 0)) break;
    double u = rng.uniform() * total;
    std::size_t pick = 0;
    while (pick + 1 < n && (u -= mass[pick]) >= 0) ++pick;
    while (mass[pick] == 0) --pick;  // rounding at the end of the scan: the last point with mass
    centres.push_back(points[pick]);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = (points[i] - centres.back()).squaredNorm();
      d2[i] = centres.size() == 1 ? d : std::min(d2[i], d);
    }
  }
  return centres;
}

}  // namespace kmeans_detail

// At most k clusters of the weighted points (fewer when they hold fewer distinct points; weights
// must be > 0; k >= 1, max_iterations >= 1). Lloyd iterations run until no point changes cluster, at most max_iterations times.
// A cluster left empty keeps its centre during the iterations and is dropped at the end.
template <class Point>
KMeansResult<Point> kMeans(const std::vector<Point>& points, const std::vector<double>& weights, int k,
                           RandomStream& rng, int max_iterations = 100) {
  using kmeans_detail::nearestCentre;
  if (k < 1 || max_iterations < 1 || weights.size() != points.size())
    throw std::invalid_argument("kMeans: k or max_iterations below 1, or one weight per point missing");
  std::vector<Point> centres = kmeans_detail::seedCentres(points, weights, k, rng);
  std::vector<int> cluster(points.size(), -1);
  std::vector<double> weight(centres.size());
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    bool changed = false;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const int c = nearestCentre(points[i], centres);
      changed |= c != cluster[i];
      cluster[i] = c;
    }
    if (!changed) break;  // (iteration 0 always changes: clusters start at -1)
    std::vector<Point> sum(centres.size(), Point::Zero());
    std::fill(weight.begin(), weight.end(), 0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      sum[cluster[i]] += weights[i] * points[i];
      weight[cluster[i]] += weights[i];
    }
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (weight[c] > 0) centres[c] = sum[c] / weight[c];
  }
  // The centres are the means of the last assignment: every iteration recomputes them from the
  // assignment it made, and the last assignment changed nothing (or was the last iteration's).
  KMeansResult<Point> result;
  std::vector<int> relabel(centres.size(), -1);
  std::fill(weight.begin(), weight.end(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) weight[cluster[i]] += weights[i];
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (!(weight[c] > 0)) continue;
    relabel[c] = int(result.centres.size());
    result.centres.push_back(centres[c]);
    result.weight.push_back(weight[c]);
  }
  result.cluster.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) result.cluster[i] = relabel[cluster[i]];
  return result;
}

}  // namespace vdbappear
