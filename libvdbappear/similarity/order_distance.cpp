#include "libvdbappear/similarity/order_distance.h"

#include "libvdbappear/math/constants.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

std::vector<double> tableCdf(const std::vector<double>& table) {
  std::vector<double> cdf(table.size() + 1, 0.0);
  const double width = 2.0 / double(table.size());
  for (std::size_t i = 0; i < table.size(); ++i) cdf[i + 1] = cdf[i] + 2 * kPi * table[i] * width;
  return cdf;
}

namespace {

// A CDF given at the edges of equal bins over [-1,1], linear in between.
double cdfAt(const std::vector<double>& cdf, double mu) {
  const int bins = int(cdf.size()) - 1;
  const double u = std::clamp((mu + 1) / 2 * bins, 0.0, double(bins));
  const int i = std::min(bins - 1, int(u));
  const double t = u - i;
  return cdf[i] * (1 - t) + cdf[i + 1] * t;
}

}  // namespace

double similarityDistance(const std::vector<double>& input_cdf, const std::vector<double>& altered_table, double alpha) {
  const std::vector<double> altered_cdf = tableCdf(altered_table);
  // Evaluation points: the edges of both grids, merged; between two of them both CDFs are linear.
  std::vector<double> edges;
  for (const std::vector<double>* cdf : {&input_cdf, &altered_cdf}) {
    const int bins = int(cdf->size()) - 1;
    for (int i = 0; i <= bins; ++i) edges.push_back(-1 + 2.0 * i / bins);
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double distance = 0;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    const double mid = (edges[i] + edges[i + 1]) / 2;
    distance += std::abs(cdfAt(input_cdf, mid) - alpha * cdfAt(altered_cdf, mid)) * (edges[i + 1] - edges[i]);
  }
  return distance;
}

}  // namespace vdbappear
