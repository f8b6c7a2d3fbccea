#include "libvdbappear/lobes/lobe_order.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace vdbappear {

std::vector<int> matchLobeSlots(const std::vector<NdfSamples>& reference, const std::vector<NdfSamples>& lobes) {
  const int slots = int(reference.size()), m = int(lobes.size());
  if (m > slots || slots > kMaxOrderedLobes)
    throw std::invalid_argument("matchLobeSlots: more lobes than reference slots, or too many slots");
  std::vector<std::vector<double>> cost(m, std::vector<double>(slots));  // cost[j][s]: lobe j in slot s
  for (int j = 0; j < m; ++j)
    for (int s = 0; s < slots; ++s) cost[j][s] = sphereL2DistanceSquared(reference[s], lobes[j]);
  std::vector<int> order(slots), best;
  std::iota(order.begin(), order.end(), 0);
  double best_cost = std::numeric_limits<double>::infinity();
  do {  // lobe j takes slot order[j]; orders that differ only past m repeat a cost and never win
    double total = 0;
    for (int j = 0; j < m; ++j) total += cost[j][order[j]];
    if (total < best_cost) {
      best_cost = total;
      best.assign(order.begin(), order.begin() + m);
    }
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

}  // namespace vdbappear
