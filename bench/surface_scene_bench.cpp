// Google Benchmark of SurfaceScene::intersect on the bumpy ball (docs/displacement.md §1, §9): its
// bumps map shell-mapped over 8 x 4 tiles of a sphere, laid out as triangles (every tile's own) or as
// one tile's triangles per latitude band and turned Embree instances of it (what vdb_render builds).
// Rays from the experiment's camera toward random points about the ball (some miss). One thread; the
// triangles are the baseline, measured in the same run.
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/procedural/height_maps.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/sphere_shell.h"

#include <benchmark/benchmark.h>

#include <vector>

namespace vdbappear {
namespace {

struct ProbeRay {
  Vec3 o, d;
};

std::vector<ProbeRay> raysTowardTheBall(const SphereShell& shell, int count) {
  const Vec3 camera(0.8, -4.2, 1.6);
  RandomStream random(11, {0});
  std::vector<ProbeRay> rays;
  for (int k = 0; k < count; ++k) {
    const Point2 a = random.uniform2(), b = random.uniform2();
    const Vec3 target = shell.centre + 1.1 * shell.radius * Vec3(2 * a.x() - 1, 2 * a.y() - 1, 2 * b.x() - 1);
    rays.push_back({camera, (target - camera).normalized()});
  }
  return rays;
}

void intersectBall(benchmark::State& state, bool turned_copies) {
  const int cells = int(state.range(0));
  const HeightField bumps = bumpsHeightMap(cells, 1);
  const SphereShell shell = SphereShell::ofTiles(Vec3::Zero(), 1.0, 8, 4);
  SurfaceScene scene;
  if (turned_copies) {
    std::vector<RigidMotion> turns;
    for (int a = 0; a < shell.tiles_x; ++a) turns.push_back(shell.turn(a));
    for (int b = 0; b < shell.tiles_y; ++b) scene.addGlossy(shellTileTriangles(bumps, shell, 1, 0, b), 0, {}, turns);
  } else {
    scene.addGlossy(shellTriangles(bumps, shell, 1), 0);
  }
  scene.commit();
  const std::vector<ProbeRay> rays = raysTowardTheBall(shell, 1 << 16);
  int hits = 0;
  for (auto _ : state)
    for (const ProbeRay& ray : rays) hits += bool(scene.intersect(ray.o, ray.d, 0, 100));
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] = benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BallAsTriangles(benchmark::State& state) { intersectBall(state, false); }
void BM_BallAsTurnedCopies(benchmark::State& state) { intersectBall(state, true); }
BENCHMARK(BM_BallAsTriangles)->ArgName("cells")->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BallAsTurnedCopies)->ArgName("cells")->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace vdbappear

BENCHMARK_MAIN();
