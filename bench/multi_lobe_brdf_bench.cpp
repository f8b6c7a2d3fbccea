// Google Benchmark of a prefiltered model's shading on the square tile (docs/displacement.md §8):
// MultiLobeBrdf::eval, ::sample and ::lobePdf, Eq. (4.5)'s sum over six lobes of the base BRDF as a coarse cell of
// vdb_displacement_prefilter holds them, against the base BRDF's own eval (one GGX lobe), the
// baseline measured in the same run; and PinholeCamera::ray, which every path starts with. Random
// directions over the upper hemisphere, lobes tilted up to 40 degrees. One thread.
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/render/camera.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace vdbappear {
namespace {

const MicrofacetBrdf kGlossyBase(MicrofacetDistribution(MicrofacetKind::GGX, 0.15), Rgb::Constant(0.6),
                                 Rgb(0.15, 0.1, 0.05));  // the experiment's glossy base (section 5)

struct DirectionPair {
  Vec3 wi, wo;
};

std::vector<DirectionPair> hemispherePairs(int count) {
  RandomStream random(3, {0});
  std::vector<DirectionPair> pairs;
  for (int k = 0; k < count; ++k) pairs.push_back({sampleCosineHemisphere(random.uniform2()),
                                                   sampleCosineHemisphere(random.uniform2())});
  return pairs;
}

VmfMixture sixTiltedLobes() {
  RandomStream random(5, {0});
  VmfMixture ndf;
  for (int k = 0; k < 6; ++k) {
    const double theta = 0.7 * random.uniform(), phi = 2 * 3.141592653589793 * random.uniform();
    ndf.lobes.push_back({1.0 / 6, 20 + 200 * random.uniform(),
                         Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))});
  }
  return ndf;
}

template <typename Brdf>
void evalOverPairs(benchmark::State& state, const Brdf& eval) {
  const std::vector<DirectionPair> pairs = hemispherePairs(1 << 14);
  Rgb sum = Rgb::Zero();
  for (auto _ : state)
    for (const DirectionPair& p : pairs) sum += eval(p.wi, p.wo);
  benchmark::DoNotOptimize(sum);
  state.counters["evals_per_s"] = benchmark::Counter(double(pairs.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BaseBrdfEval(benchmark::State& state) {
  evalOverPairs(state, [](const Vec3& wi, const Vec3& wo) { return kGlossyBase.eval(wo, wi); });
}

void BM_MultiLobeEval(benchmark::State& state) {
  const MultiLobeBrdf f(sixTiltedLobes(), kGlossyBase);
  evalOverPairs(state, [&f](const Vec3& wi, const Vec3& wo) { return f.eval(wi, wo); });
}

// MultiLobeBrdf::sample: a lobe, its direction, and the mixture's pdf and weight (Eq. 4.5).
void BM_MultiLobeSample(benchmark::State& state) {
  const MultiLobeBrdf f(sixTiltedLobes(), kGlossyBase);
  const std::vector<DirectionPair> pairs = hemispherePairs(1 << 14);
  RandomStream random(7, {0});
  std::vector<double> u(3 * pairs.size());
  for (double& v : u) v = random.uniform();
  Rgb sum = Rgb::Zero();
  for (auto _ : state)
    for (std::size_t k = 0; k < pairs.size(); ++k)
      sum += f.sample(pairs[k].wo, u[3 * k], Point2(u[3 * k + 1], u[3 * k + 2])).weight;
  benchmark::DoNotOptimize(sum);
  state.counters["samples_per_s"] = benchmark::Counter(double(pairs.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// MultiLobeBrdf::lobePdf: the mixture's density at a direction, what the prefiltered SVBRDF's
// sampling on a plane adds once per draw to fold a draw below the horizon above it
// (prefilter/prefiltered_brdf.cpp, foldedPdf).
void BM_MultiLobePdf(benchmark::State& state) {
  const MultiLobeBrdf f(sixTiltedLobes(), kGlossyBase);
  evalOverPairs(state, [&f](const Vec3& wi, const Vec3& wo) { return Rgb::Constant(f.lobePdf(wo, wi)); });
}

void BM_CameraRay(benchmark::State& state) {
  const PinholeCamera camera({Vec3(-8.8, -20, 16.8), Vec3(8, 8, 0), Vec3(0, 0, 1), 34}, 192, 144);
  double footprint = 0;
  for (auto _ : state)
    for (int y = 0; y < 144; ++y)
      for (int x = 0; x < 192; ++x) footprint += camera.ray(x + 0.5, y + 0.5).spread;
  benchmark::DoNotOptimize(footprint);
  state.counters["rays_per_s"] = benchmark::Counter(192.0 * 144, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_BaseBrdfEval)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MultiLobeEval)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MultiLobeSample)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MultiLobePdf)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CameraRay)->Unit(benchmark::kMicrosecond);

}  // namespace vdbappear

BENCHMARK_MAIN();
