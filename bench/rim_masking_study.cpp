// Not a benchmark: a measurement that scripts/ball_error_diagnosis.py runs (--checks rim-masking;
// docs/displacement.md §9 "Where the ball's rim loses its light"). Past a curved base's silhouette
// the camera sees only the upper parts of the bumps, with nothing of the surface in front of them.
// Does R (Eq. 4.12) differ there from the mean that T S holds?
//
// For coarse cells drawn at random, R's sums as a table bin adds them (the original's and the
// model's light toward wo, each times its patch's visible projected area, Eq. 4.8) over a window of
// the map about the cell, with and without the map's cells in front of it (toward the camera). The
// cells whose centre stands above the mean of the 6 x 6 coarse cells about them are the "upper"
// ones. Prints R of all cells with the map in front (what the tables average), R of the upper cells
// with nothing in front (what the rim shows), and the model's T S over the same upper cells, each
// weighed by the model's light as a bin weighs it. With --base-curvature also R of every cell over
// that base, and of its upper and lower cells apart (docs/displacement.md §6, "The relief term").
#include "libvdbappear/image/height_map_file.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>

namespace vdbappear {
namespace {

struct Settings {
  std::string map, manifest;
  double theta_i = 40, theta_o = 87, azimuth = 133;  // degrees; the lit rim's (ball_error_diagnosis.py)
  int cells = 120, halo = 8, samples_per_side = 24;
  double base_curvature = 0;  // > 0: also R of all cells with the map in front over a base so curved
  std::uint64_t seed = 7;
};

Vec3 direction(double theta_degrees, double phi_degrees) {
  const double theta = theta_degrees * M_PI / 180, phi = phi_degrees * M_PI / 180;
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

HeightField window(const HeightField& field, int i0, int j0, int cells_x, int cells_y) {
  HeightField w(cells_x, cells_y, field.cellSize());
  for (int j = 0; j <= cells_y; ++j)
    for (int i = 0; i <= cells_x; ++i) w.at(i, j) = field.at(i0 + i, j0 + j);
  return w;
}

struct Sums {
  double original = 0, model = 0, tables = 0;
  double ratio() const { return original / model; }
};

void run(const Settings& s) {
  const HeightField fine = readHeightMap(s.map);
  const PrefilteredSurfaceFile file = readPrefilteredSurface(s.manifest);
  const HeightField& coarse = file.surface.height;
  const int F = file.info.factor, n = coarse.cellsX(), halo = s.halo;
  if (fine.cellsX() != F * n || fine.cellsY() != F * coarse.cellsY() || n < 2 * halo + 2 || coarse.cellsY() < 2 * halo + 2)
    throw std::invalid_argument(s.map + " is not the map that " + s.manifest + " was prefiltered from, or is too small");
  // The camera toward -y: the map's cells in front of cell (u, v) are those of rows below v.
  const Vec3 wo = direction(s.theta_o, -90), wi = direction(s.theta_i, -90 + s.azimuth);
  EffectiveBrdfSettings e;
  e.samples_per_side = s.samples_per_side;
  const PatchBrdf one = [](const Vec3&, const Vec3&, const Vec3&, const Vec3&) { return Rgb(Rgb::Ones()); };
  RandomStream random(s.seed, {0});
  Sums all_in_front, upper_alone, curved, curved_upper, curved_lower;
  for (int k = 0; k < s.cells; ++k) {
    const Point2 p = random.uniform2();
    const int u = halo + std::min(int(p.x() * (n - 2 * halo - 1)), n - 2 * halo - 2);
    const int v = halo + std::min(int(p.y() * (coarse.cellsY() - 2 * halo - 1)), coarse.cellsY() - 2 * halo - 2);
    const bool upper = window(coarse, u, v, 1, 1).meanHeight() > window(coarse, u - 2, v - 2, 6, 6).meanHeight();
    const MultiLobeBrdf f_low(file.surface.ndfs[std::size_t(u) + std::size_t(n) * v], file.base);
    const double T_S = file.surface.scaling(Point2((u + 0.5) / n, (v + 0.5) / coarse.cellsY()), wi, wo)[0];
    for (const int kind : {0, 1, 2}) {  // the map in front; nothing in front (upper cells); curved
      const bool in_front = kind != 1;
      if ((kind == 1 && !upper) || (kind == 2 && !(s.base_curvature > 0))) continue;
      const int front = in_front ? halo : 0;  // coarse rows kept in front of the cell
      const double curvature = kind == 2 ? s.base_curvature : 0;
      const MicroGeometry original(window(fine, (u - halo) * F, (v - front) * F, (2 * halo + 1) * F, (front + halo + 1) * F), {}, curvature);
      const MicroGeometry low(window(coarse, u - halo, v - front, 2 * halo + 1, front + halo + 1), {}, curvature);
      e.seed = s.seed + 1 + k;
      const EffectiveBrdf o = effectiveBrdf(original, halo * F, front * F, F, microfacetPatchBrdf(file.base), wi, wo, e);
      const EffectiveBrdf g = effectiveBrdf(low, halo, front, 1, one, wi, wo, e);
      const double model = f_low.eval(wi, wo)[0] * g.value[0] * g.visible_area;
      Sums& sums = kind == 0 ? all_in_front : kind == 1 ? upper_alone : curved;
      sums.original += o.value[0] * o.visible_area;
      sums.model += model;
      sums.tables += T_S * model;
      if (kind == 2) {
        Sums& half = upper ? curved_upper : curved_lower;
        half.original += o.value[0] * o.visible_area;
        half.model += model;
        half.tables += T_S * model;
      }
    }
  }
  std::printf("theta_i %g, theta_o %g, azimuth %g: R of all cells with the map in front %.4f (T S %.4f); "
              "of the upper cells with nothing in front %.4f (T S %.4f, %+.1f%%)\n",
              s.theta_i, s.theta_o, s.azimuth, all_in_front.ratio(), all_in_front.tables / all_in_front.model,
              upper_alone.ratio(), upper_alone.tables / upper_alone.model,
              100 * (upper_alone.tables / upper_alone.original - 1));
  if (s.base_curvature > 0)
    std::printf("  over a base of curvature %g, all cells with the map in front: R %.4f (T S %.4f, %+.1f%%)\n", s.base_curvature,
                curved.ratio(), curved.tables / curved.model, 100 * (curved.tables / curved.original - 1));
  if (s.base_curvature > 0)
    std::printf("  over it, the upper cells: R %.4f (T S %+.1f%%), the lower: R %.4f (T S %+.1f%%)\n", curved_upper.ratio(),
                100 * (curved_upper.tables / curved_upper.original - 1), curved_lower.ratio(),
                100 * (curved_lower.tables / curved_lower.original - 1));
}

}  // namespace
}  // namespace vdbappear

int main(int argc, char** argv) {
  vdbappear::Settings s;
  CLI::App app("R at a curved base's rim: the upper cells with nothing in front against T S (red channel).\n"
               "Example: rim_masking_study ball.exr ball_8x_shadowing.json --theta-o 87", "rim_masking_study");
  app.add_option("map", s.map, "the original height map")->required();
  app.add_option("manifest", s.manifest, "its prefiltered model (vdb_displacement_prefilter's manifest)")->required();
  app.add_option("--theta-i", s.theta_i, "the light's angle from the normal, degrees")->check(CLI::Range(0.0, 89.9));
  app.add_option("--theta-o", s.theta_o, "the view's angle from the normal, degrees")->check(CLI::Range(0.0, 89.9));
  app.add_option("--azimuth", s.azimuth, "between the light and the view, degrees")->check(CLI::Range(0.0, 180.0));
  app.add_option("--cells", s.cells, "coarse cells drawn")->check(CLI::Range(1, 100000));
  app.add_option("--halo", s.halo, "coarse cells of the map kept about each (and in front of it)")->check(CLI::Range(1, 64));
  app.add_option("--samples-per-side", s.samples_per_side, "positions per estimate, per side")->check(CLI::Range(1, 200));
  app.add_option("--seed", s.seed, "draws the cells and the positions");
  app.add_option("--base-curvature", s.base_curvature, "also R over a base of this curvature (1 / world units)")
      ->check(CLI::Range(0.0, 1e6));
  CLI11_PARSE(app, argc, argv);
  try {
    vdbappear::run(s);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "rim_masking_study: %s\n", error.what());
    return 1;
  }
}
