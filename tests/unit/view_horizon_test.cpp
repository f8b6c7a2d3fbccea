// S with nodes of the view on the horizon (prefilter/scaling_tables.h, AngularScaling::view_horizon;
// docs/displacement.md §6, "The view's horizon"): read as before between the bin centres, toward
// the horizon nodes beyond the outermost ones (and at them below the horizon); made with the bins
// unchanged and the nodes evaluated at their angle; none needed by a flat map; kept by the files.
#include "libvdbappear/math/concentric_mapping.h"
#include "libvdbappear/prefilter/displacement_prefilter.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/prefilter/scaling_factorization.h"

#include "support/height_fields.h"
#include "support/prefiltered_file_errors.h"
#include "support/prefilter_settings.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace vdbappear {
namespace {

// S of N = 5 with horizon nodes: each entry a linear function of wo's square position's x (0 at the
// square's left edge, 1 at its right), so that reading it back shows where the nodes lie.
AngularScaling linearInViewX() {
  AngularScaling S;
  S.resolution = 5;
  S.view_horizon = true;
  const int N = 5, V = 7;
  S.values.resize(std::size_t(N) * N * V * V);
  const auto position = [&](int k) { return k == 0 ? 0.0 : k == N + 1 ? 1.0 : (k - 0.5) / N; };
  for (int ib = 0; ib < N; ++ib)
    for (int ia = 0; ia < N; ++ia)
      for (int ob = 0; ob < V; ++ob)
        for (int oa = 0; oa < V; ++oa) S.values[S.index(ia, ib, oa, ob)] = Rgb::Constant(2 + 3 * position(oa) + ia);
  return S;
}

TEST(ViewHorizon, TablesReadTowardTheHorizonBeyondTheOutermostBins) {
  const AngularScaling S = linearInViewX();
  const Vec3 wi = S.binDirection(1, 2);
  // At every bin centre, the bin's own value (node k + 1 of bin k).
  for (int ob = 0; ob < 5; ++ob)
    for (int oa = 0; oa < 5; ++oa)
      EXPECT_NEAR(S(wi, S.binDirection(oa, ob))[0], S.values[S.index(1, 2, oa + 1, ob + 1)][0], 1e-9) << oa << ", " << ob;
  // Linear in the square's x from edge to edge, the stretches beyond the outermost centres included.
  for (double x = 0.001; x < 1; x += 0.01) {
    const Vec3 wo = squareToHemisphere({x, 0.55});
    EXPECT_NEAR(S(wi, wo)[0], 2 + 3 * x + 1, 1e-9) << x;
  }
  // On the horizon and below it, the horizon node's value (the edge of the square), continuous there.
  EXPECT_NEAR(S(wi, Vec3(1, 0, 0))[0], 2 + 3 + 1, 1e-9);
  EXPECT_NEAR(S(wi, Vec3(1, 0, -0.3).normalized())[0], 2 + 3 + 1, 1e-9);
  EXPECT_NEAR(S(wi, Vec3(-1, 0, -0.1).normalized())[0], 2 + 0 + 1, 1e-9);
  // The negative control: without horizon nodes the same bins are clamped beyond the outermost centre.
  AngularScaling clamped;
  clamped.resolution = 5;
  for (int ib = 0; ib < 5; ++ib)
    for (int ia = 0; ia < 5; ++ia)
      for (int ob = 0; ob < 5; ++ob)
        for (int oa = 0; oa < 5; ++oa) clamped.values.push_back(S.values[S.index(ia, ib, oa + 1, ob + 1)]);
  EXPECT_NEAR(clamped(wi, Vec3(1, 0, 0))[0], 2 + 3 * 0.9 + 1, 1e-9);
  EXPECT_NEAR(clamped(wi, squareToHemisphere({0.5, 0.55}))[0], S(wi, squareToHemisphere({0.5, 0.55}))[0], 1e-12);
}

// An R that grows as the view grazes, as a coarse model's ratio to the original's visible projected
// area does (1 / (cos theta_o + 0.05)).
ScalingSample grazingView(int, int, std::uint64_t, const Vec3& wi, const Vec3& wo) {
  return {Rgb::Constant((1 + 0.2 * wi.z()) / (wo.z() + 0.05)), Rgb::Ones()};
}

FactorizationSettings smallSettings(double view_horizon_degrees) {
  FactorizationSettings s;
  s.spatial_resolution = 2;
  s.angular_resolution = 9;
  s.pairs_per_spatial_bin = 50;
  s.positions_per_angular_bin = 4;
  s.view_horizon_degrees = view_horizon_degrees;
  return s;
}

TEST(ViewHorizon, NodesAddTheHorizonAndKeepEveryBin) {
  for (const bool shared : {false, true}) {
    FactorizationSettings without = smallSettings(0), with = smallSettings(88);
    without.shared_positions = with.shared_positions = shared;
    const FactorizedScaling a = factorizeScaling(grazingView, 4, 4, without), b = factorizeScaling(grazingView, 4, 4, with);
    const int N = 9;
    ASSERT_EQ(b.S.values.size(), std::size_t(N * N * 11 * 11));
    EXPECT_EQ(tableBins(with), 4u + std::uint64_t(N * N * 11 * 11));
    for (int ib = 0; ib < N; ++ib)
      for (int ia = 0; ia < N; ++ia)
        for (int ob = 0; ob < N; ++ob)
          for (int oa = 0; oa < N; ++oa)  // the same bins, bit for bit: their random numbers are keyed as before
            ASSERT_EQ(a.S.values[a.S.index(ia, ib, oa, ob)][0], b.S.values[b.S.index(ia, ib, oa + 1, ob + 1)][0]);
    // The horizon nodes hold R at 88 degrees (R here is direction-only: exactly, but for footnote
    // 2's epsilon of 1e-6 in the sums of 4 positions).
    const double cos88 = std::cos(88 * kPi / 180);
    for (int ia = 0; ia < N; ++ia) {
      const double expected = (1 + 0.2 * b.S.binDirection(ia, 4).z()) / (cos88 + 0.05);
      EXPECT_NEAR(b.S.values[b.S.index(ia, 4, 0, 5)][0], expected, 1e-6 * expected);
      EXPECT_NEAR(b.S.values[b.S.index(ia, 4, 10, 10)][0], expected, 1e-6 * expected);
    }
    // Read at a view of 87 degrees: the nodes follow R's growth, the clamped table stays at 80 degrees'.
    const Vec3 wi = Vec3(0.3, 0.1, 0.9).normalized();
    const double theta = 87 * kPi / 180;
    const Vec3 wo(std::sin(theta), 0, std::cos(theta));
    const double exact = grazingView(0, 0, 0, wi, wo).original[0];
    const auto error = [&](const FactorizedScaling& f) { return std::abs(f(Point2(0.5, 0.5), wi, wo)[0] / exact - 1); };
    EXPECT_LT(error(b), 0.25) << "shared " << shared;
    EXPECT_GT(error(a), 0.5) << "shared " << shared;
  }
  EXPECT_THROW(factorizeScaling(grazingView, 4, 4, smallSettings(90)), std::invalid_argument);
}

// A flat map needs no scaling at grazing views either: its horizon nodes are 1, shadowing and
// interreflection alike (Eq. 4.5's f'_low of a flat map is the base BRDF, the view not limited).
TEST(ViewHorizon, FlatMapNeedsNoScalingAtTheHorizon) {
  HeightField flat(32, 32, 0.01);
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) flat.at(i, j) = 0.05;
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.factorization.view_horizon_degrees = 88;
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1));
  for (ScalingKind kind : {ScalingKind::Shadowing, ScalingKind::Interreflection}) {
    s.scaling = kind;
    const PrefilteredSurface p = prefilterDisplacement(flat, base, s);
    ASSERT_TRUE(p.scaling.S.view_horizon);
    for (const Rgb& v : p.scaling.S.values) EXPECT_LT((v - 1).abs().maxCoeff(), 2e-3) << v.transpose();
  }
}

TEST(ViewHorizon, FilesKeepTheNodes) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.scaling = ScalingKind::Shadowing;
  s.factorization.view_horizon_degrees = 88;
  s.stretches = {TileStretch::diagonal(0.5, 1)};
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1));
  const PrefilteredSurfaceFile written{prefilterDisplacement(bumpy, base, s), base, {"map.exr", 8, 0.32, 1.0, ScalingKind::Shadowing}};
  const test::TempDir dir;
  const std::string manifest = dir.path("bumpy_8x.json");
  writePrefilteredSurface(written, manifest, {});
  const PrefilteredSurfaceFile read = readPrefilteredSurface(manifest);
  ASSERT_TRUE(read.surface.scaling.S.view_horizon);
  ASSERT_TRUE(read.surface.stretched.at(0).scaling.S.view_horizon);
  const Vec3 wi = Vec3(0.5, 0.1, 0.8).normalized();
  for (const Vec3& wo : {Vec3(-0.2, 0.4, 0.9).normalized(), Vec3(0.99, 0.0, 0.1).normalized(), Vec3(0, 1, 0)}) {
    EXPECT_LT((read.surface.scaling(Point2(0.3, 0.7), wi, wo) - written.surface.scaling(Point2(0.3, 0.7), wi, wo)).abs().maxCoeff(), 1e-5);
    EXPECT_LT((read.surface.stretched[0].scaling(Point2(0.3, 0.7), wi, wo) -
               written.surface.stretched[0].scaling(Point2(0.3, 0.7), wi, wo)).abs().maxCoeff(), 1e-5);
  }
  // A manifest that claims no horizon nodes for an S that has them names the file and its size.
  nlohmann::json m;
  std::ifstream(manifest) >> m;
  m["view_horizon"] = false;
  std::ofstream(manifest) << m.dump();
  const std::string error = test::readPrefilteredSurfaceError(manifest);
  EXPECT_NE(error.find("bumpy_8x.S.exr"), std::string::npos) << "an S of the wrong width: '" << error << "'";
}

}  // namespace
}  // namespace vdbappear
