// Stretched tiles (surface/tile_stretch.h): the effective BRDF of a map squeezed along x, or
// squeezed and sheared, computed on the stretched micro-geometry itself, equals the map's own at
// the mapped directions with each facet weighed by 1 / |A^-T m| and the base BRDF at the stretched
// facet. Negative controls: the map's effective BRDF at the surface's own directions (a tile taken
// as square, what a prefiltered model did on a sphere toward the poles), and at the mapped
// directions without the weight.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/prefilter/displacement_prefilter.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/surface/tile_stretch.h"

#include "support/sphere_quadrature.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <cstdio>

namespace vdbappear {
namespace {

using test::directionFromDegrees;

// A smooth bumpy surface of period 1 along x and 0.5 along y, slopes up to about 1.3.
double bumps(double x, double y) {
  return 0.06 * std::sin(2 * kPi * x) * std::sin(4 * kPi * y) + 0.03 * std::cos(2 * kPi * (2 * x + 2 * y) + 0.7);
}

// cells_x x cells_y of side cell_size sampling bumps(M^-1 (x, y)): the map stretched by
// A = [[M, 0], [0, 1]]. Where M shears, the stretched cells' triangles are not the map's
// triangles stretched, which the identity leaves as an error of order cell^2 (measured at the
// sheared M below at 60 degrees: 3.0% at cells of 1/64, 0.86% at 1/128).
HeightField sampled(int cells_x, int cells_y, double cell_size, const TileStretch& stretch, double amplitude = 1) {
  const Eigen::Matrix2d inverse = stretch.matrix().inverse();
  HeightField field(cells_x, cells_y, cell_size);
  for (int j = 0; j <= cells_y; ++j)
    for (int i = 0; i <= cells_x; ++i) {
      const Eigen::Vector2d at = inverse * Eigen::Vector2d(i * cell_size, j * cell_size);
      field.at(i, j) = amplitude * bumps(at.x(), at.y());
    }
  return field;
}

HeightField sampled(int cells_x, int cells_y, double cell_size, double squeeze) {
  return sampled(cells_x, cells_y, cell_size, TileStretch::diagonal(squeeze, 1));
}

TEST(TileStretch, MapsDirectionsAndNormalsByTheAffineMap) {
  const TileStretch stretch = TileStretch::diagonal(0.5, 1);
  EXPECT_TRUE(TileStretch().isIdentity());
  EXPECT_FALSE(stretch.isIdentity());
  const Vec3 w = Vec3(1, 1, 1).normalized();
  EXPECT_NEAR((stretch.toMap(w) - Vec3(2, 1, 1).normalized()).norm(), 0, 1e-15);
  EXPECT_NEAR((stretch.normalOnSurface(w) - Vec3(2, 1, 1).normalized()).norm(), 0, 1e-15);
  EXPECT_NEAR(stretch.facetWeight(Vec3::UnitZ()), 1, 1e-15);   // a flat facet: area and shading both det A
  EXPECT_NEAR(stretch.facetWeight(Vec3::UnitX()), 0.5, 1e-15);  // a wall facing x keeps its area
  // The shear of a mesh's UVs: a normal stays normal to the stretched plane.
  const TileStretch shear((Eigen::Matrix2d() << 1.2, 0.4, 0.1, 0.8).finished());
  const Vec3 n = Vec3(0.3, -0.2, 1).normalized(), a = Vec3(1, 0, -0.3), b = Vec3(0, 1, 0.2);  // n . a = n . b = 0
  const Vec3 n_on = shear.normalOnSurface(n);
  auto onSurface = [&](const Vec3& t) {
    const Eigen::Vector2d xy = shear.matrix() * t.head<2>();
    return Vec3(xy.x(), xy.y(), t.z());
  };
  EXPECT_NEAR(n_on.dot(onSurface(a)), 0, 1e-15);
  EXPECT_NEAR(n_on.dot(onSurface(b)), 0, 1e-15);
}

// Eq. (4.6) over the stretched micro-geometry against tile_stretch.h's identity over the map, for
// a squeeze along x and for the same squeeze sheared (M = [[0.5, 0], [0.5, 1]], where a slip between
// A^-1, A^-T and their transposes would show: a diagonal M cannot tell them apart). Both patches
// hold whole periods of bumps (the map's 128^2 cells one period along x and two along y; the
// stretched 64^2 cells, whatever M, each line along y one period and the patch one along x), in
// fields three patches wide so that shadows from outside them fall in.
TEST(TileStretch, StretchedMapsEffectiveBrdfIsTheMapsAtMappedDirections) {
  const double cell = 1.0 / 128;
  const MicroGeometry map(sampled(384, 384, cell, 1));
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb::Constant(0.04), Rgb(0.7, 0.55, 0.4));
  EffectiveBrdfSettings settings;
  settings.samples_per_side = 300;
  const PatchBrdf on_surface = microfacetPatchBrdf(base);
  for (const TileStretch& stretch : {TileStretch::diagonal(0.5, 1), TileStretch((Eigen::Matrix2d() << 0.5, 0, 0.5, 1).finished())}) {
    const MicroGeometry surface(sampled(192, 192, cell, stretch));
    for (const auto& directions : {std::pair{directionFromDegrees(50, 0), directionFromDegrees(40, 160)},
                                   std::pair{directionFromDegrees(60, 150), directionFromDegrees(65, 0)},
                                   std::pair{directionFromDegrees(35, 90), directionFromDegrees(55, 200)}}) {
      const Vec3 wi = directions.first, wo = directions.second;
      const Vec3 vi = stretch.toMap(wi), vo = stretch.toMap(wo);
      const PatchBrdf weighted = [&](const Vec3&, const Vec3& m, const Vec3&, const Vec3&) {
        const Frame frame = Frame::fromNormal(stretch.normalOnSurface(m));
        return Rgb(base.eval(frame.toLocal(wo), frame.toLocal(wi)) * stretch.facetWeight(m));
      };
      // effectiveBrdf() is f_eff cos theta_i (Eq. 4.6 carries <w_m, wi>), hence the ratio of cosines.
      const double surface_value = effectiveBrdf(surface, 64, 64, 64, on_surface, wi, wo, settings).value.mean();
      const double mapped = effectiveBrdf(map, 128, 128, 128, weighted, vi, vo, settings).value.mean() * wi.z() / vi.z();
      const double unweighted = effectiveBrdf(map, 128, 128, 128, on_surface, vi, vo, settings).value.mean() * wi.z() / vi.z();
      const double square = effectiveBrdf(map, 128, 128, 128, on_surface, wi, wo, settings).value.mean();
      std::printf("M (%.1f %.1f; %.1f %.1f) theta_i %.0f: mapped %.4f unweighted %.3f square %.3f of the surface's\n",
                  stretch.matrix()(0, 0), stretch.matrix()(0, 1), stretch.matrix()(1, 0), stretch.matrix()(1, 1),
                  std::acos(wi.z()) * 180 / kPi, mapped / surface_value, unweighted / surface_value, square / surface_value);
      // Measured, squeezed: mapped / surface 0.9995, 1.0014, 0.9990; unweighted 1.45, 3.32, 1.06;
      // square 1.47, 2.35, 1.13. Sheared: mapped 0.9974, 0.9914, 0.9998; unweighted 1.71, 5.00, 1.032;
      // square 1.51, 3.42, 0.937.
      EXPECT_NEAR(mapped / surface_value, 1, 0.02) << "theta_i " << std::acos(wi.z()) * 180 / kPi;
      EXPECT_GT(std::abs(unweighted / surface_value - 1), 0.025);
      EXPECT_GT(std::abs(square / surface_value - 1), 0.05);
    }
  }
}

// R (single bounce) at `paths_side`^2 paths per estimate, into S of N^2 x N^2 bins (16 positions
// each) and one T bin.
DisplacementPrefilterSettings shadowingSettings(int paths_side, int N) {
  DisplacementPrefilterSettings settings;
  settings.scaling = ScalingKind::Shadowing;
  settings.samples_per_side = paths_side;
  settings.factorization.spatial_resolution = 1;
  settings.factorization.angular_resolution = N;
  settings.factorization.pairs_per_spatial_bin = 100;
  settings.factorization.positions_per_angular_bin = 16;
  return settings;
}

// h_low's bilinear surface squeezed along x by `squeeze`, sampled at cells of side `cell` (finer than
// h_low's, so that two triangles per cell follow the bilinear surface whether squeezed or not).
HeightField bilinearSqueezed(const HeightField& low, double cell, double squeeze) {
  const double side = low.cellSize();
  HeightField field(int(std::lround(low.cellsX() * side * squeeze / cell)), int(std::lround(low.cellsY() * side / cell)), cell);
  for (int j = 0; j <= field.cellsY(); ++j)
    for (int i = 0; i <= field.cellsX(); ++i) {
      const double x = i * cell / squeeze / side, y = j * cell / side;
      const int a = std::min(int(x), low.cellsX() - 1), b = std::min(int(y), low.cellsY() - 1);
      const double fx = x - a, fy = y - b;
      field.at(i, j) = (1 - fy) * ((1 - fx) * low.at(a, b) + fx * low.at(a + 1, b)) + fy * ((1 - fx) * low.at(a, b + 1) + fx * low.at(a + 1, b + 1));
    }
  return field;
}

// A prefiltered model shades a squeezed tile as tile_stretch.h derives (prefilter/prefiltered_brdf.h):
// on the squeezed h_low, f_low at the mapped directions with the fine lobes weighed and the coarse
// facet's weight divided out, against the squeezed original, is as close as the square model on the
// square h_low is to the square original at the mapped directions. The map is 3 x 3 periods of
// bumps, the patches the middle period (in fields that hold all, so shadows from outside fall in).
// Negative controls: the model with no stretch (what vdb_render did toward a sphere's poles), and
// with the coarse facets' weight left out.
TEST(TileStretch, PrefilteredModelOfASqueezedTileIsAsCloseAsOfTheSquare) {
  const double cell = 1.0 / 64;
  const HeightField fine = sampled(192, 192, cell, 1);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb::Constant(0.04), Rgb(0.7, 0.55, 0.4));
  const PrefilteredSurface surface = prefilterDisplacement(fine, base, shadowingSettings(8, 5));
  const PrefilteredBrdf model(surface, base, PrefilteredBrdf::Base::kPlane);
  const TileStretch stretch = TileStretch::diagonal(0.5, 1);
  const MicroGeometry original(fine), low(bilinearSqueezed(surface.height, 1.0 / 32, 1));
  const MicroGeometry original_squeezed(sampled(96, 192, cell, 0.5)), low_squeezed(bilinearSqueezed(surface.height, 1.0 / 32, 0.5));
  EffectiveBrdfSettings positions;
  positions.samples_per_side = 200;
  const auto mapPosition = [](const Vec3& x, double squeeze) { return Point2(x.x() / squeeze / 3, x.y() / 3); };
  for (const auto& directions : {std::pair{directionFromDegrees(50, 0), directionFromDegrees(40, 160)},
                                 std::pair{directionFromDegrees(60, 150), directionFromDegrees(45, 0)},
                                 std::pair{directionFromDegrees(35, 90), directionFromDegrees(55, 200)}}) {
    const Vec3 wi = directions.first, wo = directions.second;
    const Vec3 vi = stretch.toMap(wi), vo = stretch.toMap(wo);
    const PatchBrdf square_model = [&](const Vec3& x, const Vec3&, const Vec3& i, const Vec3& o) {
      return model.eval(mapPosition(x, 1), i, o);
    };
    // The middle period: map cells [64, 128) along x, [64, 96) along y (period 0.5) when squeezed.
    const double square = effectiveBrdf(low, 32, 32, 32, square_model, vi, vo, positions).value.mean() /
                          effectiveBrdf(original, 64, 64, 64, microfacetPatchBrdf(base), vi, vo, positions).value.mean();
    const double reference = effectiveBrdf(original_squeezed, 32, 64, 32, microfacetPatchBrdf(base), wi, wo, positions).value.mean();
    const auto squeezed = [&](const TileStretch& s, bool coarse_weight) {
      const PatchBrdf squeezed_model = [&](const Vec3& x, const Vec3& n, const Vec3& i, const Vec3& o) {
        return model.eval(mapPosition(x, 0.5), i, o, s, coarse_weight ? n : Vec3::UnitZ());
      };
      return effectiveBrdf(low_squeezed, 16, 32, 16, squeezed_model, wi, wo, positions).value.mean() / reference;
    };
    const double stretched = squeezed(stretch, true), unstretched = squeezed({}, true), no_coarse_weight = squeezed(stretch, false);
    // Measured against the square model's ratio: stretched 0.984, 0.984, 1.013; unstretched 0.94,
    // 0.84, 1.066; without the coarse weight 0.933, 0.945, 0.939.
    EXPECT_NEAR(stretched / square, 1, 0.03);
    EXPECT_GT(std::abs(unstretched / square - 1), 0.05);
    EXPECT_GT(std::abs(no_coarse_weight / square - 1), 0.05);
  }
}

// Tables made for the squeezed tile itself (DisplacementPrefilterSettings::stretches,
// PrefilteredSurface::stretched): the model on the squeezed h_low, reading them, against the squeezed
// original, over four direction pairs, is closer on average than with the square tile's tables read
// at the mapped directions (the test above). The bumps at half their height, so that squeezed they
// are as steep as the test above's square ones; N = 9. Measured: own tables 1.119, 1.088, 1.010,
// 1.004 of the original (mean |error| 0.055); the square's 1.040, 1.187, 1.005, 1.066 (0.075); the
// square model on the square map at the mapped directions 1.063, 1.172, 1.010, 1.106. So the tables'
// own error (N = 9, 16 positions per bin) is of the size of what the stretch costs.
TEST(TileStretch, TablesMadeForASqueezedTileFitItAsTheSquaresFitTheSquare) {
  const double cell = 1.0 / 64;
  const HeightField fine = sampled(192, 192, cell, TileStretch(), 0.5);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb::Constant(0.04), Rgb(0.7, 0.55, 0.4));
  const TileStretch stretch = TileStretch::diagonal(0.5, 1);
  DisplacementPrefilterSettings settings = shadowingSettings(16, 9);
  settings.stretches = {stretch};
  const PrefilteredSurface surface = prefilterDisplacement(fine, base, settings);
  ASSERT_EQ(surface.stretched.size(), 1u);
  PrefilteredSurface square_only = surface;
  square_only.stretched.clear();
  const PrefilteredBrdf model(surface, base, PrefilteredBrdf::Base::kPlane);
  const PrefilteredBrdf square_model(square_only, base, PrefilteredBrdf::Base::kPlane);
  const MicroGeometry original(fine), low(bilinearSqueezed(surface.height, 1.0 / 32, 1));
  const MicroGeometry original_squeezed(sampled(96, 192, cell, stretch, 0.5)), low_squeezed(bilinearSqueezed(surface.height, 1.0 / 32, 0.5));
  EffectiveBrdfSettings positions;
  positions.samples_per_side = 200;
  const auto mapPosition = [](const Vec3& x, double squeeze) { return Point2(x.x() / squeeze / 3, x.y() / 3); };
  double own_error = 0, square_tables_error = 0;
  for (const auto& directions : {std::pair{directionFromDegrees(50, 0), directionFromDegrees(40, 160)},
                                 std::pair{directionFromDegrees(60, 150), directionFromDegrees(45, 0)},
                                 std::pair{directionFromDegrees(35, 90), directionFromDegrees(55, 200)},
                                 std::pair{directionFromDegrees(70, 10), directionFromDegrees(30, 180)}}) {
    const Vec3 wi = directions.first, wo = directions.second;
    const PatchBrdf on_square = [&](const Vec3& x, const Vec3&, const Vec3& i, const Vec3& o) {
      return model.eval(mapPosition(x, 1), i, o);
    };
    // The square model against the square original at the mapped directions (the same light and view
    // as the squeezed tile's up to its facets' weights, tile_stretch.h).
    const Vec3 vi = stretch.toMap(wi), vo = stretch.toMap(wo);
    const double square = effectiveBrdf(low, 32, 32, 32, on_square, vi, vo, positions).value.mean() /
                          effectiveBrdf(original, 64, 64, 64, microfacetPatchBrdf(base), vi, vo, positions).value.mean();
    const double reference = effectiveBrdf(original_squeezed, 32, 64, 32, microfacetPatchBrdf(base), wi, wo, positions).value.mean();
    const auto squeezed = [&](const PrefilteredBrdf& m) {
      const PatchBrdf on_squeezed = [&](const Vec3& x, const Vec3& n, const Vec3& i, const Vec3& o) {
        return m.eval(mapPosition(x, 0.5), i, o, stretch, n);
      };
      return effectiveBrdf(low_squeezed, 16, 32, 16, on_squeezed, wi, wo, positions).value.mean() / reference;
    };
    const double own = squeezed(model), square_tables = squeezed(square_model);
    std::printf("theta_i %.0f: square model / original %.4f; squeezed with its own tables %.4f, with the square's %.4f\n",
                std::acos(wi.z()) * 180 / kPi, square, own, square_tables);
    own_error += std::abs(own - 1) / 4;
    square_tables_error += std::abs(square_tables - 1) / 4;
  }
  std::printf("mean |ratio - 1|: own tables %.4f, the square's %.4f\n", own_error, square_tables_error);
  EXPECT_LT(own_error, square_tables_error);
}

}  // namespace
}  // namespace vdbappear
