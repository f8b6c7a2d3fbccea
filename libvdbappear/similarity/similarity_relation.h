#pragma once
// High-order similarity relations (Zhao, Ramamoorthi and Bala 2014, "High-Order Similarity
// Relations in Radiative Transfer"): altered parameters sigma_a* = sigma_a, sigma_s* = alpha sigma_s
// and a phase function f* whose Legendre moments satisfy Eq. (23), found by Algorithm 1. Light
// header.

#include <string>
#include <vector>

namespace vdbappear {

// A 1-D phase function as Algorithm 1 sees it: its Legendre moments f_0 = 1 .. f_{N0} (Eq. 8), its
// normalised support nz(f) (§7.3; 1 for HG, which is positive everywhere), and the cumulative
// distribution of mu at equal steps over [-1,1] (tableCdf; for the distance rule).
struct PhaseMoments {
  std::vector<double> moments;
  double support = 1;
  std::vector<double> cdf;
};
PhaseMoments henyeyGreensteinPhaseMoments(double g, int max_order);
// A table on equal bins ascending over [-1,1] (docs/medium.md §6); normalised here.
PhaseMoments tablePhaseMoments(const std::vector<double>& table, int max_order);

// How the order N is chosen among those Theorem 1 allows (docs/similarity.md §1):
enum class OrderRule {
  kSupport,   // Algorithm 1 as printed: the highest order whose table is not overfitting (§7.3)
  kDistance,  // the order whose f* is closest to f (similarityDistance, order_distance.h)
};

struct SimilarityOptions {
  double alpha = 0;             // sigma_s* / sigma_s (Eq. 22); 0: defaultAlpha(f_1)
  int max_order = 5;            // N0 of Algorithm 1
  double support_ratio = 0.65;  // beta of §7.3: reject f* when nz(f*) < beta nz(f) (kSupport)
  int bins = 360;               // k of Eq. (30)
  OrderRule order_rule = OrderRule::kDistance;
};
OrderRule parseOrderRule(const std::string& name);  // "support" or "distance"
const char* orderRuleName(OrderRule rule);

// §7.2: alpha = max(0.3, 1 - f_1), capped at 1 (backward-scattering media are not altered further).
double defaultAlpha(double f1);
// Below (1 - f_1) / 2, Eq. (23) gives f_1* < -1: no phase function exists even at order 1.
double minimumAlpha(double f1);

// Eq. (23): f_0* = 1, f_n* = 1 - (1 - f_n) / alpha.
std::vector<double> alteredMoments(const std::vector<double>& moments, double alpha);

// One order that Algorithm 1 solved and rejected (lines 11-14).
struct RejectedOrder {
  int order = 0;
  double support = 0;   // nz(f*) of its table; 0 if the QP found none
  double distance = 0;  // similarityDistance of its table (kDistance); 0 if not computed
  std::string reason;
};

struct AlteredPhase {
  double alpha = 1;
  int order = 0;                             // N: the relations hold for n = 0..N
  std::vector<double> moments;               // f_0* .. f_N*, which the table matches
  std::vector<double> existence_margins;     // [n]: Theorem 1's margin at order n, n = 1 .. as far as tested
  std::vector<RejectedOrder> rejected;       // higher orders tried and rejected, highest first
  std::vector<double> table;                 // f*(mu) on `bins` bins ascending over [-1,1], normalised
  double support = 0;                        // nz(f*)
  double input_support = 1;                  // nz(f)
  double distance = 0;                       // similarityDistance of the table (kDistance; else 0)
  // Every order's table fell below the support threshold (Algorithm 1 would run out of orders):
  // the widest table was kept, ties going to the higher order.
  bool support_below_threshold = false;
};

// Algorithm 1: the highest order N <= N0 whose relations Theorem 1 allows (lines 4-10), then the
// QP of Eq. (31) at order N, N-1, ... With kSupport, until the table is not overfitting
// (nz(f*) >= beta nz(f), §7.3) and the QP found it (lines 11-14); if no order passes, the widest
// table (see above). With kDistance, while the next lower order's table is closer to f
// (similarityDistance): the first order whose lower neighbour is no closer is taken, which is the
// closest order when the distances fall and then rise with N (as measured: docs/similarity.md).
// Throws std::invalid_argument when alpha is outside [minimumAlpha(f_1), 1] or the input has fewer
// than N0+1 moments.
//
// warm: the tables of the previous phase function, by order, kept up to date here. Along a sequence
// of nearby phase functions (ascending g levels) each QP then starts from its neighbour's table and
// takes a few active-set steps instead of an interior-point solve; the result is the same.
struct QpWarmStarts {
  std::vector<std::vector<double>> table_of_order;  // [N]: the last table solved at order N; empty if none
};
AlteredPhase computeAlteredPhase(const PhaseMoments& phase, const SimilarityOptions& options,
                                 QpWarmStarts* warm = nullptr);

}  // namespace vdbappear
