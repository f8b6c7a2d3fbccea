// Google Benchmark of the weight optimisation's training renders (§6.3 of the downsampling paper;
// issue 19): the paper's training set, the six face views of about 100 pixels under the four sh1
// skies (optimize/training_set.h), of the coloured twill (vdb_make_medium twill --yarns 8 --res
// 128) and of its reduction by 4 with 2 lobes and K = 2 (Table 2 row 5, as in make optimize).
// Each benchmark iteration renders the 24 images as one SGD iteration does: twice, with fresh seeds,
// at 4 spp each (vdb_optimize_weights --spp 8), the reduction with its gradient images.
//
// What the optimisation needs is low noise in the restricted means mean_k(I_r) (Eq. 14), so the
// counters are about them:
// - noise: the RMS over images, clusters and channels of c_r * sd(mean_k(I_r)), the standard
//   deviation of one render's restricted mean relative to the image (c_r = 1 / max(mean, 0.05),
//   Eq. 14), estimated from the two renders' differences over all iterations;
// - var_seconds: noise^2 times the seconds of one set of 24 images: the time to a given noise is
//   proportional to it, so the ratio of two rows is their ratio of time to equal noise.
// Pixel sets: the reduction's clusters seen by camera rays, within its own foreground (alpha > 0.5;
// the optimiser takes the full medium's). Arguments: medium (0: the reduction, with gradients; 1:
// the full twill), light strategy (render/volume_path_tracer.h: 0 auto, 1 mis, 2 light, 3 phase).
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/optimize/restricted_means.h"
#include "libvdbappear/optimize/training_images.h"
#include "libvdbappear/optimize/training_set.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/render/render_image.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

namespace vdbappear {
namespace {

struct TrainingMedia {
  std::shared_ptr<const MediumView> full, reduced;
};

const TrainingMedia& twill() {
  static const TrainingMedia media = [] {
    WeaveParams weave;
    weave.resolution = 128;
    weave.yarns = 8;
    const MediumPtr full = makeWeave(weave);
    MultiLobeOptions options;
    options.factor = 4;
    options.fit.forced_lobes = 2;
    options.clustering.clusters = 2;
    const MediumPtr reduced = downsampleMultiLobe(*full, options).medium;
    return TrainingMedia{std::make_shared<MediumView>(full, Interpolation::kNearest),
                         std::make_shared<MediumView>(reduced, Interpolation::kNearest)};
  }();
  return media;
}

// The pixel sets of every training image: the reduction's clusters seen by camera rays (16 per
// pixel), within its foreground.
std::vector<ClusterMasks> pixelSets(TrainingScenes& reduced) {
  std::vector<ClusterMasks> sets;
  for (std::size_t i = 0; i < reduced.size(); ++i) {
    RenderSettings coverage = trainingRenderSettings(reduced.config(i).view, 16, 0, PathSettings{});
    coverage.cluster_coverage = true;
    coverage.path.max_depth = 0;
    const RenderResult r = reduced.render(i, coverage, nullptr);
    ClusterMasks masks(r);
    masks.restrictToForeground(r.alpha);
    sets.push_back(std::move(masks));
  }
  return sets;
}

void BM_TrainingSet(benchmark::State& state) {
  const TrainingMedia& media = twill();
  const bool full = state.range(0) == 1;
  PathSettings path;
  path.strategy = LightStrategy(state.range(1));
  const std::vector<TrainingConfig> configs = trainingSet(media.reduced->worldBounds(), 100, "sh1", kFaces);
  TrainingScenes reduced(media.reduced, configs);
  TrainingScenes scenes(full ? media.full : media.reduced, configs);
  const std::vector<ClusterMasks> sets = pixelSets(reduced);

  double sum_squares = 0;  // of c_r * (mean_k(A) - mean_k(B)), over images, clusters, channels, iterations
  std::uint64_t terms = 0, paths = 0;
  std::int64_t seed = 1;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      std::array<RenderResult, 2> halves;
      for (RenderResult& half : halves) {
        RenderSettings s = trainingRenderSettings(configs[i].view, 4, std::uint64_t(seed++), path);
        s.weight_gradients = !full;
        half = scenes.render(i, s, nullptr);
        paths += half.paths;
      }
      const std::vector<Rgb> a = restrictedMeans(halves[0].mean, sets[i]);
      const std::vector<Rgb> b = restrictedMeans(halves[1].mean, sets[i]);
      const Rgb c = ((foregroundMean(halves[0].mean, sets[i]) + foregroundMean(halves[1].mean, sets[i])) / 2).max(0.05).inverse();
      for (int k = 0; k < sets[i].clusters(); ++k) {
        if (sets[i].count(k) == 0) continue;
        sum_squares += (c * (a[k] - b[k])).square().sum();
        terms += 3;
      }
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // Var(A - B) = 2 Var(A): the noise of one render's restricted mean.
  const double noise = terms ? std::sqrt(sum_squares / terms / 2) : 0.0;
  const double seconds_per_set = seconds / double(state.iterations());
  state.counters["noise"] = noise;
  state.counters["var_seconds"] = noise * noise * seconds_per_set;
  state.counters["paths_per_second"] = double(paths) / seconds;
}

BENCHMARK(BM_TrainingSet)
    ->ArgNames({"full", "strategy"})
    ->Args({0, 1})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Args({1, 0})
    ->Unit(benchmark::kSecond)
    ->MinTime(20.0);

}  // namespace
}  // namespace vdbappear

BENCHMARK_MAIN();
