#include "libvdbappear/similarity/similarity_relation.h"

#include "libvdbappear/similarity/altered_phase_qp.h"
#include "libvdbappear/similarity/legendre_moments.h"
#include "libvdbappear/similarity/moment_existence.h"
#include "libvdbappear/similarity/order_distance.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

// The resolution of an analytic phase function's CDF for the distance rule: ten times the QP's bins.
constexpr int kDistanceBins = 3600;

PhaseMoments henyeyGreensteinPhaseMoments(double g, int max_order) {
  return {henyeyGreensteinMoments(g, max_order), 1.0, tableCdf(tabulateHenyeyGreenstein(g, kDistanceBins))};
}

PhaseMoments tablePhaseMoments(const std::vector<double>& table, int max_order) {
  const std::vector<double> normalised = normalisedTable(table);
  return {tableMoments(normalised, max_order), tableSupport(normalised), tableCdf(normalised)};
}

OrderRule parseOrderRule(const std::string& name) {
  if (name == "support") return OrderRule::kSupport;
  if (name == "distance") return OrderRule::kDistance;
  throw std::invalid_argument("--order-rule '" + name + "': expected support or distance");
}

const char* orderRuleName(OrderRule rule) { return rule == OrderRule::kSupport ? "support" : "distance"; }

double defaultAlpha(double f1) { return std::min(1.0, std::max(0.3, 1 - f1)); }

double minimumAlpha(double f1) { return (1 - f1) / 2; }

std::vector<double> alteredMoments(const std::vector<double>& moments, double alpha) {
  std::vector<double> altered(moments.size(), 1.0);
  for (std::size_t n = 1; n < moments.size(); ++n) altered[n] = 1 - (1 - moments[n]) / alpha;
  return altered;
}

namespace {

std::vector<double> firstMoments(const std::vector<double>& moments, int order) {
  return {moments.begin(), moments.begin() + order + 1};
}

void checkInputs(const PhaseMoments& phase, const SimilarityOptions& options, double alpha) {
  if (options.max_order < 1) throw std::invalid_argument("the highest order N0 must be at least 1");
  if (int(phase.moments.size()) < options.max_order + 1)
    throw std::invalid_argument(fmt::format("need the phase function's moments up to order {}", options.max_order));
  if (options.bins < options.max_order + 3) throw std::invalid_argument(fmt::format("need more than {} bins", options.max_order + 2));
  const double f1 = phase.moments[1];
  if (!(alpha <= 1) || !(alpha >= minimumAlpha(f1)) || !(alpha > 0))
    throw std::invalid_argument(fmt::format(
        "alpha {:g} outside [{:g}, 1]: below (1 - f1) / 2 = {:g} (f1 = {:g}) the altered mean cosine f1* falls "
        "below -1 and no phase function exists",
        alpha, minimumAlpha(f1), minimumAlpha(f1), f1));
}

std::string noTable(const SimilarityOptions& options, const PhaseTableSolution& solution) {
  return fmt::format("no table on {} bins satisfies the moments (QP code {})", options.bins, solution.termination);
}

// The QP of Eq. (31) for these moments, from the warm start of its order if there is one. (A start
// from another order's table was measured slower: it seldom converges within kWarmStartSteps.)
PhaseTableSolution solveOrder(const std::vector<double>& target, int bins, QpWarmStarts* warm) {
  if (!warm) return solveAlteredPhaseTable(target, bins);
  const std::size_t order = target.size() - 1;
  if (warm->table_of_order.size() <= order) warm->table_of_order.resize(order + 1);
  std::vector<double>& start = warm->table_of_order[order];
  PhaseTableSolution solution = solveAlteredPhaseTable(target, bins, start.empty() ? nullptr : &start);
  if (solution.feasible) start = solution.table;
  return solution;
}

// Lines 11-14: solve, stepping down while the table overfits (or the QP finds none at k bins).
// When every order overfits, the widest table wins (ties: the higher order).
AlteredPhase firstOrderNotOverfitting(const PhaseMoments& phase, const SimilarityOptions& options,
                                      const std::vector<double>& altered, int order, AlteredPhase result,
                                      QpWarmStarts* warm) {
  const double min_support = options.support_ratio * phase.support;
  AlteredPhase widest;
  for (; order >= 1; --order) {
    const std::vector<double> target = firstMoments(altered, order);
    PhaseTableSolution solution = solveOrder(target, options.bins, warm);
    const double support = solution.feasible ? tableSupport(solution.table) : 0.0;
    if (solution.feasible && support > widest.support) {
      widest.order = order;
      widest.moments = target;
      widest.table = solution.table;
      widest.support = support;
    }
    if (solution.feasible && support >= min_support) {
      result.order = order;
      result.moments = target;
      result.table = std::move(solution.table);
      result.support = support;
      return result;
    }
    result.rejected.push_back({order, support, 0.0,
                               solution.feasible ? fmt::format("support {:.3f} < {:g} x {:.3f} (overfitting, §7.3)", support,
                                                               options.support_ratio, phase.support)
                                                 : noTable(options, solution)});
  }
  if (widest.order == 0) throw std::runtime_error("the QP of Eq. (31) found no table at any order; try more bins");
  result.order = widest.order;
  result.moments = std::move(widest.moments);
  result.table = std::move(widest.table);
  result.support = widest.support;
  result.support_below_threshold = true;
  result.rejected.erase(std::remove_if(result.rejected.begin(), result.rejected.end(),
                                      [&](const RejectedOrder& r) { return r.order == result.order; }),
                        result.rejected.end());
  return result;
}

// The distance rule: from the highest order down, while the next lower order's table is closer to f.
AlteredPhase closestOrder(const PhaseMoments& phase, const SimilarityOptions& options, const std::vector<double>& altered,
                          int order, AlteredPhase result, QpWarmStarts* warm) {
  if (phase.cdf.size() < 2) throw std::invalid_argument("the distance rule needs the phase function's CDF");
  for (; order >= 1; --order) {
    const std::vector<double> target = firstMoments(altered, order);
    PhaseTableSolution solution = solveOrder(target, options.bins, warm);
    if (!solution.feasible) {
      result.rejected.push_back({order, 0.0, 0.0, noTable(options, solution)});
      continue;
    }
    const double distance = similarityDistance(phase.cdf, solution.table, result.alpha);
    const double support = tableSupport(solution.table);
    if (result.order != 0 && distance >= result.distance) {
      result.rejected.push_back({order, support, distance,
                                 fmt::format("distance {:.4f} >= {:.4f} of order {}", distance, result.distance, result.order)});
      break;
    }
    if (result.order != 0)
      result.rejected.push_back({result.order, result.support, result.distance,
                                 fmt::format("distance {:.4f} > {:.4f} of order {}", result.distance, distance, order)});
    result.order = order;
    result.moments = target;
    result.table = std::move(solution.table);
    result.support = support;
    result.distance = distance;
  }
  if (result.order == 0) throw std::runtime_error("the QP of Eq. (31) found no table at any order; try more bins");
  return result;
}

}  // namespace

AlteredPhase computeAlteredPhase(const PhaseMoments& phase, const SimilarityOptions& options, QpWarmStarts* warm) {
  AlteredPhase result;
  result.alpha = options.alpha > 0 ? options.alpha : defaultAlpha(phase.moments.at(1));
  checkInputs(phase, options, result.alpha);
  result.input_support = phase.support;
  const std::vector<double> altered = alteredMoments(firstMoments(phase.moments, options.max_order), result.alpha);

  // Lines 4-10: the highest order whose relations are satisfiable (order 1 is, by checkInputs).
  int order = 1;
  result.existence_margins.push_back(checkMomentsExist(firstMoments(altered, 1)).margin);
  while (order < options.max_order) {
    const MomentExistence next = checkMomentsExist(firstMoments(altered, order + 1));
    result.existence_margins.push_back(next.margin);
    if (!next.exists) break;
    ++order;
  }

  return options.order_rule == OrderRule::kDistance
             ? closestOrder(phase, options, altered, order, std::move(result), warm)
             : firstOrderNotOverfitting(phase, options, altered, order, std::move(result), warm);
}

}  // namespace vdbappear
