// Not a benchmark: a measurement (docs/displacement.md §9, "Where the planes' error under the
// sun comes from"). A planar map under a sun, seen by a pinhole camera: the image's mean for the
// original and for each model, from the prefilter's own estimators (Eq. 4.6-4.8) over every coarse
// cell, each cell seen along its own view and weighed by the pixels it covers (1 / (d^2 cos^3 alpha),
// alpha its angle off the camera's axis; the estimates' visible projected area carries the rest). It
// has no render noise, so it splits the full model's error into its parts:
//   - T: the full model against the same with T = 1 (Eq. 4.21's spatial table);
//   - S's read: T = 1 against S exact, the map's own ratio sum(original) / sum(multi-lobe) at the
//     views of a G x G grid of groups of cells (each cell read at its group's ratio);
//   - what is left with S exact and T = 1: the rank-one model at this light and these views, and
//     the groups' width.
// With --bins-radius, S's read splits again: every bin of S within that many degrees of the sun and
// (twice as far) of the central view made anew as the map's ratio at the bin's directions over
// every coarse cell ("true bins"), so that the image with them tells the bins' draw from the read
// between bin centres. Red, green and blue are averaged, as vdb_image_compare's mean is.
#include "libvdbappear/image/height_map_file.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <CLI/CLI.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <vector>

namespace vdbappear {
namespace {

struct Settings {
  std::string map, manifest;
  // displacement_experiment.py's CAMERA and SUN (the sun's direction is the way its light travels).
  std::vector<double> camera{-0.55, -1.25, 1.05}, target{0.5, 0.5, 0}, sun{0.62, -0.38, -0.69};
  int samples_per_side = 8, groups = 6;
  double bins_radius = 0;  // degrees; 0: S's bins as stored only
  std::uint64_t seed = 12345;
};

double mean3(const Rgb& c) { return (c[0] + c[1] + c[2]) / 3; }
Vec3 vec(const std::vector<double>& v) { return Vec3(v[0], v[1], v[2]); }

// The models' light from one coarse cell toward wo: the original's over its F x F fine cells, h_low's
// with the original BRDF (naive), with f'_low (multi-lobe) and with f'_low times a scaling.
class CellLight {
 public:
  CellLight(const HeightField& fine, const PrefilteredSurfaceFile& file, const EffectiveBrdfSettings& e)
      : file_(file), original_(fine), low_(file.surface.height), e_(e), f_orig_(microfacetPatchBrdf(file.base)) {
    for (const VmfMixture& ndf : file.surface.ndfs) lobes_.emplace_back(ndf, file.base);
  }
  int cells() const { return file_.surface.height.cellsX(); }
  double original(int u, int v, const Vec3& wi, const Vec3& wo) const {
    return reflected(effectiveBrdf(original_, u * file_.info.factor, v * file_.info.factor, file_.info.factor, f_orig_, wi, wo, e_));
  }
  double naive(int u, int v, const Vec3& wi, const Vec3& wo) const {
    return reflected(effectiveBrdf(low_, u, v, 1, f_orig_, wi, wo, e_));
  }
  double multiLobe(int u, int v, const Vec3& wi, const Vec3& wo) const {
    const PatchBrdf one = [](const Vec3&, const Vec3&, const Vec3&, const Vec3&) { return Rgb(Rgb::Ones()); };
    return mean3(lobes_[std::size_t(u) + std::size_t(cells()) * v].eval(wi, wo)) *
           reflected(effectiveBrdf(low_, u, v, 1, one, wi, wo, e_));
  }
  // f_low of `model` (Eq. 4.13) at each visible point of h_low's cell, as the renderer shades it.
  double scaled(int u, int v, const Vec3& wi, const Vec3& wo, const PrefilteredBrdf& model) const {
    const double n = cells();
    return reflected(visibleAreaAverage(low_, u, v, 1, wo, e_, [&](const MicroGeometry::Point& q, int, int) {
      const double cos_i = q.normal.dot(wi);
      if (cos_i <= 0 || !low_.unoccluded(q, wi)) return Rgb(Rgb::Zero());
      return Rgb(model.eval(Point2(q.base.x() / n, q.base.y() / n), wi, wo, {}, q.normal) * cos_i);
    }));
  }

 private:
  static double reflected(const EffectiveBrdf& f) { return mean3(f.value) * f.visible_area; }
  const PrefilteredSurfaceFile& file_;
  MicroGeometry original_, low_;
  EffectiveBrdfSettings e_;
  PatchBrdf f_orig_;
  std::vector<MultiLobeBrdf> lobes_;
};

// sum over every coarse cell of f(u, v), in parallel over rows, added in a fixed order.
double overCells(int n, const std::function<double(int, int)>& f) {
  std::vector<double> rows(std::size_t(n), 0.0);
  tbb::parallel_for(0, n, [&](int v) {
    for (int u = 0; u < n; ++u) rows[std::size_t(v)] += f(u, v);
  });
  double sum = 0;
  for (const double r : rows) sum += r;
  return sum;
}

// The map's own S at (wi, wo): sum(original) / sum(multi-lobe) over every coarse cell.
double mapRatio(const CellLight& light, const Vec3& wi, const Vec3& wo) {
  const double original = overCells(light.cells(), [&](int u, int v) { return light.original(u, v, wi, wo); });
  return original / overCells(light.cells(), [&](int u, int v) { return light.multiLobe(u, v, wi, wo); });
}

PrefilteredSurface withTrueBins(const PrefilteredSurface& surface, const CellLight& light, const Vec3& wi, const Vec3& wo,
                                double radius_degrees, int* count) {
  PrefilteredSurface result = surface;
  AngularScaling& S = result.scaling.S;
  const double near_wi = std::cos(radius_degrees * M_PI / 180), near_wo = std::cos(2 * radius_degrees * M_PI / 180);
  *count = 0;
  for (int ib = 0; ib < S.resolution; ++ib)
    for (int ia = 0; ia < S.resolution; ++ia) {
      const Vec3 bin_i = S.binDirection(ia, ib);
      if (bin_i.dot(wi) < near_wi) continue;
      for (int ob = 0; ob < S.resolution; ++ob)
        for (int oa = 0; oa < S.resolution; ++oa) {
          const Vec3 bin_o = S.binDirection(oa, ob);
          if (bin_o.dot(wo) < near_wo) continue;
          S.values[S.index(ia, ib, oa, ob)] = Rgb::Constant(mapRatio(light, bin_i, bin_o));
          ++*count;
        }
    }
  return result;
}

void run(const Settings& s) {
  const PrefilteredSurfaceFile file = readPrefilteredSurface(s.manifest);
  const HeightField fine = readHeightMap(s.map, file.info.size, file.info.height_scale);
  const int n = file.surface.height.cellsX(), F = file.info.factor;
  if (fine.cellsX() != F * n || fine.cellsY() != F * file.surface.height.cellsY() || file.surface.height.cellsY() != n)
    throw std::invalid_argument(s.map + " is not the square map that " + s.manifest + " was prefiltered from");
  EffectiveBrdfSettings e;
  e.samples_per_side = s.samples_per_side;
  e.seed = s.seed;
  const CellLight light(fine, file, e);
  const Vec3 camera = vec(s.camera), axis = (vec(s.target) - camera).normalized(), wi = -vec(s.sun).normalized();
  const double size = file.info.size;
  const auto centre = [&](double u, double v) { return Vec3(u / n * size, v / n * size, 0); };
  const auto view = [&](int u, int v) { return Vec3((camera - centre(u + 0.5, v + 0.5)).normalized()); };
  const auto pixels = [&](int u, int v) {  // the image area per unit of projected area
    const Vec3 d = centre(u + 0.5, v + 0.5) - camera;
    const double cos_alpha = d.normalized().dot(axis);
    return 1 / (d.squaredNorm() * cos_alpha * cos_alpha * cos_alpha);
  };
  const auto image = [&](const std::function<double(int, int, const Vec3&)>& f) {
    return overCells(n, [&](int u, int v) { return pixels(u, v) * f(u, v, view(u, v)); });
  };
  const auto scaledBy = [&](const PrefilteredBrdf& model) {
    return image([&](int u, int v, const Vec3& wo) { return light.scaled(u, v, wi, wo, model); });
  };
  PrefilteredSurface flat = file.surface;
  for (Rgb& t : flat.scaling.T.values) t = Rgb::Ones();
  const PrefilteredBrdf full(file.surface, file.base, PrefilteredBrdf::Base::kPlane);
  const PrefilteredBrdf flat_T(flat, file.base, PrefilteredBrdf::Base::kPlane);

  const double original = image([&](int u, int v, const Vec3& wo) { return light.original(u, v, wi, wo); });
  const auto report = [&](const char* what, double value) {
    std::printf("%-40s %+.3f%%\n", what, 100 * (value / original - 1));
    std::fflush(stdout);
  };
  report("naive", image([&](int u, int v, const Vec3& wo) { return light.naive(u, v, wi, wo); }));
  // The multi-lobe model's light per cell (pixels times light), kept for S exact below.
  std::vector<double> multi_lobe(std::size_t(n) * n);
  report("multi-lobe", image([&](int u, int v, const Vec3& wo) {
           const double light_here = light.multiLobe(u, v, wi, wo);
           multi_lobe[std::size_t(u) + std::size_t(n) * v] = light_here;
           return light_here;
         }));
  report("full", scaledBy(full));
  report("full, T = 1", scaledBy(flat_T));
  // S exact per group of views, T = 1.
  const int G = s.groups;
  std::vector<double> exact(std::size_t(G) * G);
  for (int gy = 0; gy < G; ++gy)
    for (int gx = 0; gx < G; ++gx)
      exact[std::size_t(gx + G * gy)] = mapRatio(light, wi, (camera - centre((gx + 0.5) * n / G, (gy + 0.5) * n / G)).normalized());
  report("S exact per view group, T = 1", image([&](int u, int v, const Vec3&) {
           return multi_lobe[std::size_t(u) + std::size_t(n) * v] * exact[std::size_t(u * G / n + G * (v * G / n))];
         }));
  if (s.bins_radius > 0) {
    int count = 0;
    const Vec3 central = (camera - vec(s.target)).normalized();
    const PrefilteredSurface true_bins = withTrueBins(file.surface, light, wi, central, s.bins_radius, &count);
    PrefilteredSurface true_bins_flat = true_bins;
    true_bins_flat.scaling.T = flat.scaling.T;
    std::printf("(%d bins of S made anew over every coarse cell)\n", count);
    report("full, true bins", scaledBy(PrefilteredBrdf(true_bins, file.base, PrefilteredBrdf::Base::kPlane)));
    report("full, true bins, T = 1", scaledBy(PrefilteredBrdf(true_bins_flat, file.base, PrefilteredBrdf::Base::kPlane)));
  }
}

}  // namespace
}  // namespace vdbappear

int main(int argc, char** argv) {
  vdbappear::Settings s;
  CLI::App app("A planar map's image under a sun from the prefilter's estimators over every coarse cell: the full\n"
               "model's error in its mean split into T, S's read, and the rest (red, green and blue averaged).\n"
               "Example: sun_error_budget woven.exr woven_8x_shadowing.json --bins-radius 16", "sun_error_budget");
  app.add_option("map", s.map, "the original height map")->required();
  app.add_option("manifest", s.manifest, "its prefiltered model (vdb_displacement_prefilter's manifest)")->required();
  app.add_option("--camera", s.camera, "the pinhole's position")->expected(3);
  app.add_option("--target", s.target, "where it looks")->expected(3);
  app.add_option("--sun", s.sun, "the way the sun's light travels")->expected(3);
  app.add_option("--samples-per-side", s.samples_per_side, "positions per estimate, per side")->check(CLI::Range(1, 200));
  app.add_option("--groups", s.groups, "G: S exact at the views of G x G groups of cells")->check(CLI::Range(1, 64));
  app.add_option("--bins-radius", s.bins_radius, "degrees: S's bins this near the sun (twice as near the view) made anew")
      ->check(CLI::Range(0.0, 90.0));
  app.add_option("--seed", s.seed, "the estimates' positions");
  CLI11_PARSE(app, argc, argv);
  try {
    vdbappear::run(s);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "sun_error_budget: %s\n", error.what());
    return 1;
  }
}
