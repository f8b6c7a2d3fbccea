// Google Benchmark of Algorithm 1 over the tables of a medium with a continuous g (issue 27): the
// quantiser's levels of one g range, solved in order as vdb_similarity solves a run of them, with
// either order rule, cold (every QP by the interior-point solver) or with warm starts (each QP from
// the previous level's table of its order, altered_phase_qp.h). One thread; the baseline (the
// support rule) in the same run. Ranges: g 0.7 to 0.95 (the 256^3 cloud of docs/similarity.md §4,
// 626 levels) and -0.9 to 0.9 (4500 levels, warm only).
#include "libvdbappear/similarity/g_quantiser.h"
#include "libvdbappear/similarity/similarity_relation.h"

#include <benchmark/benchmark.h>

namespace vdbappear {
namespace {

void alterLevels(benchmark::State& state, double g_low, double g_high, OrderRule rule, bool warm_starts, int stride) {
  const GQuantiser quantiser(1e-3, 5);
  std::vector<PhaseMoments> phases;
  for (int level = quantiser.level(g_low); level <= quantiser.level(g_high); level += stride)
    phases.push_back(henyeyGreensteinPhaseMoments(quantiser.value(level), 5));
  SimilarityOptions options;
  options.order_rule = rule;
  for (auto _ : state) {
    QpWarmStarts warm;
    for (const PhaseMoments& phase : phases)
      benchmark::DoNotOptimize(computeAlteredPhase(phase, options, warm_starts ? &warm : nullptr));
  }
  state.counters["tables"] = double(phases.size());
  state.counters["s_per_table"] =
      benchmark::Counter(double(phases.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_CloudLevels(benchmark::State& state) {
  alterLevels(state, 0.7, 0.95, state.range(0) ? OrderRule::kDistance : OrderRule::kSupport, state.range(1), 1);
}
BENCHMARK(BM_CloudLevels)->ArgNames({"distance", "warm"})->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_WideLevels(benchmark::State& state) {
  alterLevels(state, -0.9, 0.9, state.range(0) ? OrderRule::kDistance : OrderRule::kSupport, true, 1);
}
BENCHMARK(BM_WideLevels)->ArgNames({"distance"})->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace vdbappear

BENCHMARK_MAIN();
