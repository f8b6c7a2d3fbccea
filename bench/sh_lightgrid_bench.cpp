// Google Benchmark of the SH light grid (dissertation ch. 5, Fig. 5.8): evaluating an 8^3 grid grows
// with the number of lights; interpolating 1M points does not. Baselines in the same run: the
// analytic SH of every light at each point (what the grid replaces), and trilinear interpolation.
// Lights: the rectangle [-1,1]^2 at z = 1.5, facing down, cut into 1, 8, 64 or 512 triangles.
#include "libvdbappear/lightgrid/sh_light_grid.h"
#include "libvdbappear/lightgrid/zonal_factorisation.h"

#include <benchmark/benchmark.h>

#include <random>

namespace vdbappear {
namespace {

constexpr int kLmax = 8;

std::vector<PolygonLight> triangleLights(int count) {
  if (count == 1) return {PolygonLight{{Vec3(-1, -1, 1.5), Vec3(1, 1, 1.5), Vec3(1, -1, 1.5)}, Vec3(1, 1, 1)}};
  int nx = 1, ny = 1;  // count / 2 quads, as square as possible
  while (nx * ny * 2 < count) (nx <= ny ? nx : ny) *= 2;
  std::vector<PolygonLight> lights;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double x0 = -1 + 2.0 * i / nx, x1 = -1 + 2.0 * (i + 1) / nx, y0 = -1 + 2.0 * j / ny, y1 = -1 + 2.0 * (j + 1) / ny;
      // clockwise seen from +z: the normal points down, toward the grid
      lights.push_back({{Vec3(x0, y0, 1.5), Vec3(x1, y1, 1.5), Vec3(x1, y0, 1.5)}, Vec3(1, 1, 1)});
      lights.push_back({{Vec3(x0, y0, 1.5), Vec3(x0, y1, 1.5), Vec3(x1, y1, 1.5)}, Vec3(1, 1, 1)});
    }
  return lights;
}

const ShGridLayout kLayout = ShGridLayout::covering(Vec3(-1, -1, -1), Vec3(1, 1, 1), 8);

std::vector<Vec3> randomPoints(int count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> points(count);
  for (Vec3& p : points) p = Vec3(u(rng), u(rng), u(rng));
  return points;
}

// The ZH factorisation's lobe search, once per run of a tool (not per light or node).
void BM_ZonalFactorisation(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ZonalFactorisation(kLmax));
}

void BM_EvaluateGrid(benchmark::State& state) {
  const std::vector<PolygonLight> lights = triangleLights(int(state.range(0)));
  const ZonalFactorisation zh(kLmax);
  for (auto _ : state) benchmark::DoNotOptimize(ShLightGrid::evaluate(lights, zh, kLayout, nullptr));
  state.counters["lights"] = double(lights.size());
  state.counters["nodes"] = double(kLayout.count());
}

void interpolatePoints(benchmark::State& state, CellInterpolation method) {
  const std::vector<PolygonLight> lights = triangleLights(int(state.range(0)));
  const ShLightGrid grid = ShLightGrid::evaluate(lights, kLmax, kLayout, nullptr);
  const std::vector<Vec3> points = randomPoints(int(state.range(1)));
  std::vector<Vec3> coeffs;
  for (auto _ : state)
    for (const Vec3& p : points) {
      grid.interpolate(p, method, coeffs);
      benchmark::DoNotOptimize(coeffs.data());
    }
  state.counters["lights"] = double(lights.size());
  state.counters["points"] = double(points.size());
}
void BM_InterpolateHermite(benchmark::State& state) { interpolatePoints(state, CellInterpolation::kHermite); }
void BM_InterpolateTrilinear(benchmark::State& state) { interpolatePoints(state, CellInterpolation::kTrilinear); }

// The baseline: analytic SH of every light at every point (no grid), on fewer points.
void BM_AnalyticPerPoint(benchmark::State& state) {
  const std::vector<PolygonLight> lights = triangleLights(int(state.range(0)));
  const ZonalFactorisation zh(kLmax);
  const std::vector<Vec3> points = randomPoints(int(state.range(1)));
  for (auto _ : state)
    for (const Vec3& p : points) benchmark::DoNotOptimize(shLighting(lights, p, zh));
  state.counters["lights"] = double(lights.size());
  state.counters["points"] = double(points.size());
}

BENCHMARK(BM_ZonalFactorisation)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateGrid)->Arg(1)->Arg(8)->Arg(64)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InterpolateHermite)->Args({1, 1000000})->Args({8, 1000000})->Args({64, 1000000})->Args({512, 1000000})
    ->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_InterpolateTrilinear)->Args({1, 1000000})->Args({512, 1000000})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_AnalyticPerPoint)->Args({1, 1000})->Args({8, 1000})->Args({64, 1000})->Args({512, 100})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdbappear

BENCHMARK_MAIN();
