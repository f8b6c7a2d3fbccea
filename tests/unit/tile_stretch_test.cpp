// Stretched tiles (surface/tile_stretch.h): the effective BRDF of a map squeezed along x, computed
// on the squeezed micro-geometry itself, equals the map's own at the mapped directions with each
// facet weighed by 1 / |A^-T m| and the base BRDF at the stretched facet. Negative controls: the
// map's effective BRDF at the surface's own directions (a tile taken as square, what a prefiltered
// model did on a sphere toward the poles), and at the mapped directions without the weight.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/surface/tile_stretch.h"

#include "support/sphere_quadrature.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vdbappear {
namespace {

using test::directionFromDegrees;

// A smooth bumpy surface of period 1 along x and 0.5 along y, slopes up to about 1.3.
double bumps(double x, double y) {
  return 0.06 * std::sin(2 * kPi * x) * std::sin(4 * kPi * y) + 0.03 * std::cos(2 * kPi * (2 * x + 2 * y) + 0.7);
}

// cells x cells of side cell_size sampling bumps(x / squeeze, y): the map stretched by
// A = diag(squeeze, 1, 1).
HeightField sampled(int cells, double cell_size, double squeeze) {
  HeightField field(cells, cells, cell_size);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) field.at(i, j) = bumps(i * cell_size / squeeze, j * cell_size);
  return field;
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
  TileStretch shear;
  shear.m << 1.2, 0.4, 0.1, 0.8;
  const Vec3 n = Vec3(0.3, -0.2, 1).normalized(), a = Vec3(1, 0, -0.3), b = Vec3(0, 1, 0.2);  // n . a = n . b = 0
  const Vec3 n_on = shear.normalOnSurface(n);
  auto onSurface = [&](const Vec3& t) { return Vec3((shear.m * t.head<2>()).x(), (shear.m * t.head<2>()).y(), t.z()); };
  EXPECT_NEAR(n_on.dot(onSurface(a)), 0, 1e-15);
  EXPECT_NEAR(n_on.dot(onSurface(b)), 0, 1e-15);
}

// Eq. (4.6) over the squeezed micro-geometry against tile_stretch.h's identity over the map. Both
// patches hold whole periods of bumps (the map's 64^2 cells one period along x and two along y, the
// squeezed 32^2 one each), in fields three patches wide so that shadows from outside them fall in.
TEST(TileStretch, SqueezedMapsEffectiveBrdfIsTheMapsAtMappedDirections) {
  const double squeeze = 0.5, cell = 1.0 / 64;
  const MicroGeometry map(sampled(192, cell, 1)), surface(sampled(96, cell, squeeze));
  const TileStretch stretch = TileStretch::diagonal(squeeze, 1);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb::Constant(0.04), Rgb(0.7, 0.55, 0.4));
  EffectiveBrdfSettings settings;
  settings.samples_per_side = 300;
  const PatchBrdf on_surface = microfacetPatchBrdf(base);
  for (const auto& [wi, wo] : {std::pair{directionFromDegrees(50, 0), directionFromDegrees(40, 160)},
                               std::pair{directionFromDegrees(60, 150), directionFromDegrees(65, 0)},
                               std::pair{directionFromDegrees(35, 90), directionFromDegrees(55, 200)}}) {
    const Vec3 vi = stretch.toMap(wi), vo = stretch.toMap(wo);
    const PatchBrdf weighted = [&](const Vec3&, const Vec3& m, const Vec3&, const Vec3&) {
      const Frame frame = Frame::fromNormal(stretch.normalOnSurface(m));
      return Rgb(base.eval(frame.toLocal(wo), frame.toLocal(wi)) * stretch.facetWeight(m));
    };
    // effectiveBrdf() is f_eff cos theta_i (Eq. 4.6 carries <w_m, wi>), hence the ratio of cosines.
    const double surface_value = effectiveBrdf(surface, 32, 32, 32, on_surface, wi, wo, settings).value.mean();
    const double mapped = effectiveBrdf(map, 64, 64, 64, weighted, vi, vo, settings).value.mean() * wi.z() / vi.z();
    const double unweighted = effectiveBrdf(map, 64, 64, 64, on_surface, vi, vo, settings).value.mean() * wi.z() / vi.z();
    const double square = effectiveBrdf(map, 64, 64, 64, on_surface, wi, wo, settings).value.mean();
    // Measured: mapped / surface 0.998, 1.002, 0.996; unweighted 1.45, 3.32, 1.06; square 1.47, 2.36, 1.12.
    EXPECT_NEAR(mapped / surface_value, 1, 0.02) << "theta_i " << std::acos(wi.z()) * 180 / kPi;
    EXPECT_GT(std::abs(unweighted / surface_value - 1), 0.04);
    EXPECT_GT(std::abs(square / surface_value - 1), 0.1);
  }
}

}  // namespace
}  // namespace vdbappear
