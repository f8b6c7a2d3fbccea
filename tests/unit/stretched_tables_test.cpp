// Scaling tables for stretched tiles (docs/displacement.md §6, "Tables for stretched tiles"): a
// micro-geometry laid out stretched, the tables a flat map needs on any tile (none), the renderer's
// choice and blend of the tables nearest a stretch, and their files.
#include "libvdbappear/prefilter/displacement_prefilter.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"

#include "support/height_fields.h"
#include "support/prefiltered_file_errors.h"
#include "support/prefilter_settings.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace vdbappear {
namespace {

const MicrofacetBrdf& testBase() {
  static const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1));
  return base;
}

// Points above base positions and the points rays meet are the map's stretched, and each keeps the
// base position on the map that it lies above.
TEST(StretchedTables, MicroGeometryLaidOutStretchedIsTheMapStretched) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  const TileStretch stretch((Eigen::Matrix2d() << 0.5, 0.1, 0.0, 1.2).finished());
  const MicroGeometry map(bumpy), stretched(bumpy, stretch);
  for (const Point2& uv : {Point2(3.3, 7.8), Point2(20.1, 11.6), Point2(30.5, 0.4)}) {
    const MicroGeometry::Point a = map.at(uv.x(), uv.y()), b = stretched.at(uv.x(), uv.y());
    EXPECT_NEAR((b.base - uv).norm(), 0, 1e-12);
    const Eigen::Vector2d xy = stretch.matrix() * a.x.head<2>();
    EXPECT_NEAR((b.x - Vec3(xy.x(), xy.y(), a.x.z())).norm(), 0, 1e-12);
    EXPECT_NEAR((b.normal - stretch.normalOnSurface(a.normal)).norm(), 0, 1e-12);
    // A ray straight down onto the stretched point meets it, at the map's base position.
    const MicroGeometry::Point above{b.x + Vec3(0, 0, 1), Vec3::UnitZ(), Point2()};
    const auto hit = stretched.trace(above, -Vec3::UnitZ());
    ASSERT_TRUE(hit);
    EXPECT_NEAR((hit->x - b.x).norm(), 0, 1e-6);
    EXPECT_NEAR((hit->base - uv).norm(), 0, 1e-6);
    EXPECT_NEAR((hit->normal - b.normal).norm(), 0, 1e-9);
  }
}

// A flat map is flat on any tile: every table is one, the stretched tiles' as the square's.
TEST(StretchedTables, FlatMapNeedsNoScalingOnAnyTile) {
  HeightField flat(32, 32, 0.01);
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) flat.at(i, j) = 0.05;
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.stretches = {TileStretch::diagonal(0.5, 1), TileStretch::diagonal(0.3, 1.2)};
  for (ScalingKind kind : {ScalingKind::Shadowing, ScalingKind::Interreflection}) {
    s.scaling = kind;
    const PrefilteredSurface p = prefilterDisplacement(flat, testBase(), s);
    ASSERT_EQ(p.stretched.size(), 2u);
    for (const StretchedScaling& table : p.stretched) {
      for (const Rgb& t : table.scaling.T.values) EXPECT_LT((t - 1).abs().maxCoeff(), 1e-3) << t.transpose();
      for (const Rgb& v : table.scaling.S.values) EXPECT_LT((v - 1).abs().maxCoeff(), 2e-3) << v.transpose();
    }
  }
}

// A bumpy map's tables differ between tiles (a negative control for the test above: the estimates
// do see the stretch).
TEST(StretchedTables, BumpyMapsTablesDependOnTheTile) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.scaling = ScalingKind::Shadowing;
  s.stretches = {TileStretch::diagonal(0.4, 1)};
  const PrefilteredSurface p = prefilterDisplacement(bumpy, testBase(), s);
  double difference = 0;
  for (std::size_t k = 0; k < p.scaling.S.values.size(); ++k)
    difference = std::max(difference, std::abs(p.stretched[0].scaling.S.values[k][0] / p.scaling.S.values[k][0] - 1));
  EXPECT_GT(difference, 0.05);
}

// Tables of one constant value each, for the square tile (1), x squeezed to 0.5 (2) and to 0.25 (4).
PrefilteredSurface constantTables() {
  PrefilteredSurface p;
  p.height = HeightField(2, 2, 0.5);
  p.ndfs.assign(4, VmfMixture{{{1.0, 1e4, Vec3::UnitZ()}}});
  const auto constant = [](double value) {
    return FactorizedScaling{{1, {Rgb::Ones()}}, {1, false, {Rgb::Constant(value)}}};
  };
  p.scaling = constant(1);
  p.stretched = {{TileStretch::diagonal(0.5, 1), constant(2)}, {TileStretch::diagonal(0.25, 1), constant(4)}};
  return p;
}

// The renderer's T S on a stretched tile: a table's own stretch reads that table alone; between
// two, a blend of both, continuous as the stretch goes from the square to past the last table.
TEST(StretchedTables, ModelReadsTheNearestTablesAndBlendsContinuously) {
  const PrefilteredBrdf model(constantTables(), testBase(), PrefilteredBrdf::Base::kCurved);
  const Point2 x(0.3, 0.6);
  const Vec3 wi = Vec3(0.3, 0.2, 0.9).normalized(), wo = Vec3(-0.4, 0.1, 0.8).normalized();
  const auto scaling = [&](double squeeze) { return model.scalingOnTile(x, wi, wo, TileStretch::diagonal(squeeze, 1))[0]; };
  EXPECT_DOUBLE_EQ(scaling(1), 1);
  EXPECT_DOUBLE_EQ(scaling(0.5), 2);
  EXPECT_DOUBLE_EQ(scaling(0.25), 4);
  EXPECT_GT(scaling(0.7), 1);
  EXPECT_LT(scaling(0.7), 2);
  EXPECT_GT(scaling(0.35), 2);
  EXPECT_LT(scaling(0.35), 4);
  double previous = scaling(1.2), largest_step = 0;
  for (double squeeze = 1.2; squeeze >= 0.05; squeeze -= 0.001) {
    const double value = scaling(squeeze);
    largest_step = std::max(largest_step, std::abs(value - previous));
    previous = value;
  }
  EXPECT_LT(largest_step, 0.05) << "the blend jumps";
  // The square tile's table alone: read at the directions mapped to the square, as before.
  PrefilteredSurface square = constantTables();
  square.stretched.clear();
  EXPECT_DOUBLE_EQ(PrefilteredBrdf(square, testBase(), PrefilteredBrdf::Base::kCurved)
                       .scalingOnTile(x, wi, wo, TileStretch::diagonal(0.25, 1))[0], 1);
}

TEST(StretchedTables, RoundTripThroughTheFilesAndRefuseABrokenStretch) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.scaling = ScalingKind::Shadowing;
  s.stretches = {TileStretch::diagonal(0.6, 1), TileStretch::diagonal(0.3, 1)};
  PrefilteredSurfaceFile written{prefilterDisplacement(bumpy, testBase(), s), testBase(), {"map.exr", 8, 0.32, 1.0, ScalingKind::Shadowing}};
  const test::TempDir dir;
  const std::string manifest = dir.path("bumpy_8x.json");
  writePrefilteredSurface(written, manifest, {});
  for (const char* part : {"stretch1.T", "stretch1.S", "stretch2.T", "stretch2.S"})
    EXPECT_TRUE(std::filesystem::exists(dir.path(std::string("bumpy_8x.") + part + ".exr"))) << part;
  const PrefilteredSurfaceFile read = readPrefilteredSurface(manifest);
  ASSERT_EQ(read.surface.stretched.size(), 2u);
  const Vec3 wi = Vec3(0.5, 0.1, 0.8).normalized(), wo = Vec3(-0.2, 0.4, 0.9).normalized();
  const Point2 x(0.3, 0.7);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(read.surface.stretched[k].stretch.matrix(), written.surface.stretched[k].stretch.matrix());
    EXPECT_LT((read.surface.stretched[k].scaling(x, wi, wo) - written.surface.stretched[k].scaling(x, wi, wo)).abs().maxCoeff(), 1e-5);
  }

  nlohmann::json m;
  std::ifstream(manifest) >> m;
  m["stretched"][1]["stretch"] = {{-0.3, 0.0}, {0.0, 1.0}};  // a mirror
  std::ofstream(manifest) << m.dump();
  const std::string error = test::readPrefilteredSurfaceError(manifest);
  EXPECT_NE(error.find("bumpy_8x.json"), std::string::npos) << "a mirrored tile's tables: '" << error << "'";
  EXPECT_NE(error.find("positive determinant"), std::string::npos) << error;
  s.stretches = {TileStretch::diagonal(-0.5, 1)};
  EXPECT_THROW(prefilterDisplacement(bumpy, testBase(), s), std::invalid_argument);
}

}  // namespace
}  // namespace vdbappear
