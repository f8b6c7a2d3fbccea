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

double similarityDistance(const std::vector<double>& input_cdf, const std::vector<double>& altered_table, double alpha) {
  const std::vector<double> altered_cdf = tableCdf(altered_table);
  // Between two consecutive edges of the grids merged, both CDFs are linear: [left, right] lies in
  // input bin i - 1 and altered bin j - 1, where each CDF is interpolated at the midpoint.
  const int input_bins = int(input_cdf.size()) - 1, altered_bins = int(altered_cdf.size()) - 1;
  auto edge = [](int i, int bins) { return -1 + 2.0 * i / bins; };
  auto interpolate = [](const std::vector<double>& cdf, int bins, int bin, double mu) {
    const double t = std::clamp((mu + 1) / 2 * bins - bin, 0.0, 1.0);
    return cdf[bin] * (1 - t) + cdf[bin + 1] * t;
  };
  double distance = 0, left = -1;
  for (int i = 1, j = 1; i <= input_bins && j <= altered_bins;) {
    const double a = edge(i, input_bins), b = edge(j, altered_bins), right = std::min(a, b), mid = (left + right) / 2;
    distance += std::abs(interpolate(input_cdf, input_bins, i - 1, mid) - alpha * interpolate(altered_cdf, altered_bins, j - 1, mid)) *
                (right - left);
    i += a == right;
    j += b == right;
    left = right;
  }
  return distance;
}

}  // namespace vdbappear
