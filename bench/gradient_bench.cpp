// Google Benchmark of gradient images (Appendix A, downsampling paper; render/path_gradients.h):
// rendering the image with the gradients of every (cluster, lobe) factor against the image alone,
// in the same run, on the coloured twill (vdb_make_medium twill --yarns 8 --res 128) reduced by 4
// with (K, m) = (2, 2) and (5, 3), a 100x100 training view from +z under a sky and a sun, 8 spp.
// The bound: all gradient images together cost at most 1.5x the image alone.
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/render/render_image.h"
#include "libvdbappear/render/scene_description.h"

#include <benchmark/benchmark.h>

#include <map>

namespace vdbappear {
namespace {

std::shared_ptr<const MediumView> reducedTwill(int clusters, int lobes) {
  static std::map<std::pair<int, int>, std::shared_ptr<const MediumView>> views;
  auto& view = views[{clusters, lobes}];
  if (!view) {
    WeaveParams weave;
    weave.resolution = 128;
    weave.yarns = 8;
    MultiLobeOptions options;
    options.factor = 4;
    options.fit.forced_lobes = lobes;
    options.clustering.clusters = clusters;
    view = std::make_shared<MediumView>(downsampleMultiLobe(*makeWeave(weave), options).medium, Interpolation::kNearest);
  }
  return view;
}

void BM_Render(benchmark::State& state) {
  const auto view = reducedTwill(int(state.range(0)), int(state.range(1)));
  SceneDescription description;
  description.lights = nlohmann::json::array({{{"type", "env"}, {"radiance", 0.5}},
                                              {{"type", "sun"}, {"direction", {0.5, 0.3, -0.8}}, {"strength", 3.0}}});
  description.view = "+z";
  description.render.width = description.render.height = 100;
  description.render.spp = 8;
  description.render.weight_gradients = state.range(2) != 0;
  const RenderScene scene = buildRenderScene(description, view, {});
  const PinholeCamera camera(cameraOf(description, view.get()), 100, 100);
  for (auto _ : state) benchmark::DoNotOptimize(renderImage(scene, camera, description.render));
  state.counters["parameters"] = double(view->clusterCount() * view->lobeCount());
}

// Arguments: clusters, lobes, gradients (0: image alone).
BENCHMARK(BM_Render)->Args({2, 2, 0})->Args({2, 2, 1})->Args({5, 3, 0})->Args({5, 3, 1})->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

}  // namespace
}  // namespace vdbappear

BENCHMARK_MAIN();
