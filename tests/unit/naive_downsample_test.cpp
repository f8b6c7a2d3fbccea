// Naive downsampling (Eq. 5-6 of the downsampling paper) against a brute-force dense evaluation.
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::Vec3s;

int floorDiv(int a, int b) { return int(std::floor(double(a) / b)); }

// What Eq. (5)-(6) give for one coarse voxel, by looping over its F^3 children.
struct Expected {
  bool active = false;
  double density = 0;
  std::array<double, 3> albedo{};
  std::array<double, 6> S{};
  double hg_g = 0;
};

Expected bruteForce(const Medium& fine, const Coord& coarse, int F, SggxWeighting weighting) {
  double rho_sum = 0, s_weight = 0, scatter = 0, g_scatter = 0, g_density = 0;
  std::array<double, 3> albedo_sum{};
  std::array<double, 6> S_sum{};
  for (int dx = 0; dx < F; ++dx)
    for (int dy = 0; dy < F; ++dy)
      for (int dz = 0; dz < F; ++dz) {
        const Coord c(coarse.x() * F + dx, coarse.y() * F + dy, coarse.z() * F + dz);
        if (!fine.density->tree().isValueOn(c)) continue;  // empty children count as 0
        const double rho = fine.density->tree().getValue(c);
        if (rho <= 0) continue;
        rho_sum += rho;
        const Vec3s a = fine.albedo ? fine.albedo->tree().getValue(c) : Vec3s(1.0f);
        for (int k = 0; k < 3; ++k) albedo_sum[k] += rho * a[k];
        if (fine.sggx_diag) {
          const double w = weighting == SggxWeighting::Count ? 1.0 : rho;
          const Vec3s d = fine.sggx_diag->tree().getValue(c);
          const Vec3s o = fine.sggx_offdiag ? fine.sggx_offdiag->tree().getValue(c) : Vec3s(0.0f);
          for (int k = 0; k < 3; ++k) {
            S_sum[k] += w * d[k];
            S_sum[3 + k] += w * o[k];
          }
          s_weight += w;
        }
        if (fine.hg_g) {
          const double g = fine.hg_g->tree().getValue(c), sigma_s = rho * (double(a[0]) + a[1] + a[2]) / 3;
          g_scatter += sigma_s * g;
          scatter += sigma_s;
          g_density += rho * g;
        }
      }
  Expected e;
  e.active = rho_sum > 0;
  if (!e.active) return e;
  e.density = rho_sum / (F * F * F);
  for (int k = 0; k < 3; ++k) e.albedo[k] = albedo_sum[k] / rho_sum;
  for (int k = 0; k < 6; ++k) e.S[k] = s_weight > 0 ? S_sum[k] / s_weight : 0;
  e.hg_g = scatter > 0 ? g_scatter / scatter : g_density / rho_sum;
  return e;
}

// Compares every coarse voxel that could hold data with the brute-force result.
void expectMatchesBruteForce(const Medium& fine, const Medium& coarse, int F, SggxWeighting weighting) {
  const CoordBBox fine_box = fine.density->evalActiveVoxelBoundingBox();
  const CoordBBox box(Coord(floorDiv(fine_box.min().x(), F), floorDiv(fine_box.min().y(), F), floorDiv(fine_box.min().z(), F)),
                      Coord(floorDiv(fine_box.max().x(), F), floorDiv(fine_box.max().y(), F), floorDiv(fine_box.max().z(), F)));
  std::size_t compared = 0;
  for (auto it = box.begin(); it; ++it) {
    const Expected e = bruteForce(fine, *it, F, weighting);
    ASSERT_EQ(coarse.density->tree().isValueOn(*it), e.active) << *it;
    if (!e.active) continue;
    ++compared;
    ASSERT_NEAR(coarse.density->tree().getValue(*it), e.density, 1e-6 * e.density) << *it;
    if (fine.albedo) {
      const Vec3s a = coarse.albedo->tree().getValue(*it);
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(a[k], e.albedo[k], 1e-6) << *it;
    }
    if (fine.sggx_diag) {
      const Vec3s d = coarse.sggx_diag->tree().getValue(*it), o = coarse.sggx_offdiag->tree().getValue(*it);
      for (int k = 0; k < 3; ++k) {
        ASSERT_NEAR(d[k], e.S[k], 1e-6) << *it;
        ASSERT_NEAR(o[k], e.S[3 + k], 1e-6) << *it;
      }
    }
    if (fine.hg_g) ASSERT_NEAR(coarse.hg_g->tree().getValue(*it), e.hg_g, 1e-6) << *it;
  }
  EXPECT_GT(compared, 10u);
  EXPECT_EQ(compared, coarse.density->activeVoxelCount());
}

struct Case {
  int factor;
  SggxWeighting weighting;
  std::uint64_t seed;
};

class NaiveDownsampleVsBruteForce : public testing::TestWithParam<Case> {};

TEST_P(NaiveDownsampleVsBruteForce, MatchesEquations5And6) {
  const Case c = GetParam();
  RandomMediumParams p;
  p.extent = 37;  // odd: leaves and coarse voxels straddle the boundary; centred: negative coordinates
  p.seed = c.seed;
  p.hg_g = true;
  const MediumPtr fine = makeRandomMedium(p);
  // Other grids need not share the density's topology: drop some albedo and S leaves (their
  // background then applies) and make some albedo voxels inactive (their stored value applies).
  int k = 0;
  for (auto leaf = fine->density->tree().cbeginLeaf(); leaf; ++leaf, ++k) {
    if (k % 5 == 1) delete fine->albedo->tree().stealNode<openvdb::Vec3STree::LeafNodeType>(leaf->origin(), {}, false);
    if (k % 7 == 2) delete fine->sggx_offdiag->tree().stealNode<openvdb::Vec3STree::LeafNodeType>(leaf->origin(), {}, false);
    if (k % 3 == 0) fine->albedo->tree().setValueOff(leaf->origin(), Vec3s(0.3f, 0.6f, 0.9f));
  }
  const DownsampleResult result = downsampleNaive(*fine, {c.factor, c.weighting});
  expectMatchesBruteForce(*fine, *result.medium, c.factor, c.weighting);
  EXPECT_NO_THROW(validateMedium(*result.medium, "coarse")) << "the output is itself a valid medium";
}

INSTANTIATE_TEST_SUITE_P(
    Factors, NaiveDownsampleVsBruteForce,
    testing::Values(Case{2, SggxWeighting::Count, 1}, Case{2, SggxWeighting::Density, 2}, Case{3, SggxWeighting::Count, 3},
                    Case{3, SggxWeighting::Density, 4}, Case{4, SggxWeighting::Count, 5}, Case{5, SggxWeighting::Count, 6},
                    Case{8, SggxWeighting::Density, 7}, Case{16, SggxWeighting::Count, 8}),
    [](const testing::TestParamInfo<Case>& info) {
      return "F" + std::to_string(info.param.factor) +
             (info.param.weighting == SggxWeighting::Count ? "_count" : "_density");
    });

TEST(NaiveDownsample, MediaWithoutOptionalGridsStayWithout) {
  RandomMediumParams p;
  p.extent = 20;
  p.albedo = false;
  p.sggx = false;
  const MediumPtr fine = makeRandomMedium(p);
  const MediumPtr coarse = downsampleNaive(*fine, {2, SggxWeighting::Count}).medium;
  EXPECT_FALSE(coarse->albedo);
  EXPECT_FALSE(coarse->hasSggx());
  EXPECT_FALSE(coarse->hg_g);
  expectMatchesBruteForce(*fine, *coarse, 2, SggxWeighting::Count);
}

// Density and albedo means commute with chaining: F = 2 twice equals F = 4. So does S with density
// weights (a weighted mean of weighted means); with count weights it does not, by design.
TEST(NaiveDownsample, ChainingTwoFactorsOfTwoEqualsFactorFour) {
  const MediumPtr fine = test::randomMedium(45);
  for (SggxWeighting weighting : {SggxWeighting::Count, SggxWeighting::Density}) {
    const MediumPtr half = downsampleNaive(*fine, {2, weighting}).medium;
    const MediumPtr chained = downsampleNaive(*half, {2, weighting}).medium;
    const MediumPtr direct = downsampleNaive(*fine, {4, weighting}).medium;
    EXPECT_TRUE(test::gridsMatch(*direct->density, *chained->density, 1e-5));
    EXPECT_TRUE(test::gridsMatch(*direct->albedo, *chained->albedo, 1e-5));
    if (weighting == SggxWeighting::Density) {
      EXPECT_TRUE(test::gridsMatch(*direct->sggx_diag, *chained->sggx_diag, 1e-5));
      EXPECT_TRUE(test::gridsMatch(*direct->sggx_offdiag, *chained->sggx_offdiag, 1e-5));
    }
    EXPECT_EQ(direct->transform(), chained->transform());
  }
}

openvdb::BBoxd worldBox(const openvdb::FloatGrid& grid) {
  const CoordBBox b = grid.evalActiveVoxelBoundingBox();
  const openvdb::Vec3d lo = grid.indexToWorld(b.min().asVec3d() - openvdb::Vec3d(0.5));
  const openvdb::Vec3d hi = grid.indexToWorld(b.max().asVec3d() + openvdb::Vec3d(0.5));
  return openvdb::BBoxd(openvdb::math::minComponent(lo, hi), openvdb::math::maxComponent(lo, hi));
}

// Placement (docs/medium.md): coarse voxel I covers fine voxels F*I .. F*I+F-1.
TEST(NaiveDownsample, PreservesTheWorldRegion) {
  for (int F : {2, 3, 4}) {
    // Aligned: a box of fine voxels [-2F, 4F) fully dense at its corners, under a rotated, shifted transform.
    auto density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    auto transform = openvdb::math::Transform::createLinearTransform(0.7);
    transform->postRotate(0.3, openvdb::math::Y_AXIS);
    transform->postTranslate(openvdb::Vec3d(1.5, -2, 0.25));
    density->setTransform(transform);
    density->tree().setValue(Coord(-2 * F), 1.0f);
    density->tree().setValue(Coord(4 * F - 1), 1.0f);
    Medium fine;
    fine.density = density;
    const MediumPtr coarse = downsampleNaive(fine, {F, SggxWeighting::Count}).medium;
    const openvdb::BBoxd a = worldBox(*fine.density), b = worldBox(*coarse->density);
    EXPECT_TRUE(a.min().eq(b.min(), 1e-9) && a.max().eq(b.max(), 1e-9)) << "F=" << F << ": " << a << " vs " << b;
    EXPECT_NEAR(coarse->transform().voxelSize()[0], 0.7 * F, 1e-12);

    // Unaligned: the coarse region contains the fine one and exceeds it by less than one coarse voxel.
    density->tree().setValue(Coord(4 * F), 1.0f);
    const MediumPtr grown = downsampleNaive(fine, {F, SggxWeighting::Count}).medium;
    const openvdb::BBoxd c = worldBox(*fine.density), d = worldBox(*grown->density);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(d.min()[k], c.min()[k] + 1e-9);
      EXPECT_GE(d.max()[k], c.max()[k] - 1e-9);
    }
    EXPECT_LT((d.extents() - c.extents()).length(), std::sqrt(3.0) * 0.7 * F);
  }
}

TEST(NaiveDownsample, ActiveTilesGiveTheSameResultAsTheirVoxels) {
  const MediumPtr tiled = test::randomMedium(40);
  tiled->density->tree().fill(CoordBBox(Coord(-64), Coord(-49)), 2.5f, true);   // 8 level-1 tiles
  tiled->density->tree().fill(CoordBBox(Coord(128), Coord(255)), 0.5f, true);   // one level-2 tile
  tiled->albedo->tree().fill(CoordBBox(Coord(-64), Coord(-57)), Vec3s(0.2f, 0.4f, 0.6f), true);
  ASSERT_TRUE(tiled->density->tree().hasActiveTiles());
  Medium voxelized = *tiled;
  voxelized.density = tiled->density->deepCopy();
  voxelized.density->tree().voxelizeActiveTiles();
  ASSERT_FALSE(voxelized.density->tree().hasActiveTiles());
  for (int F : {2, 3}) {
    const MediumPtr a = downsampleNaive(*tiled, {F, SggxWeighting::Count}).medium;
    const MediumPtr b = downsampleNaive(voxelized, {F, SggxWeighting::Count}).medium;
    EXPECT_TRUE(test::gridsMatch(*b->density, *a->density, 0));
    EXPECT_TRUE(test::gridsMatch(*b->albedo, *a->albedo, 0));
    EXPECT_TRUE(test::gridsMatch(*b->sggx_diag, *a->sggx_diag, 0));
  }
  expectMatchesBruteForce(*tiled, *downsampleNaive(*tiled, {3, SggxWeighting::Count}).medium, 3, SggxWeighting::Count);
}

TEST(NaiveDownsample, ResultDoesNotDependOnTheThreadCount) {
  const MediumPtr fine = test::randomMedium(64);
  MediumPtr single;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    single = downsampleNaive(*fine, {3, SggxWeighting::Density}).medium;
  }
  const MediumPtr parallel = downsampleNaive(*fine, {3, SggxWeighting::Density}).medium;
  EXPECT_TRUE(test::gridsMatch(*single->density, *parallel->density, 0));
  EXPECT_TRUE(test::gridsMatch(*single->albedo, *parallel->albedo, 0));
  EXPECT_TRUE(test::gridsMatch(*single->sggx_diag, *parallel->sggx_diag, 0));
  EXPECT_TRUE(test::gridsMatch(*single->sggx_offdiag, *parallel->sggx_offdiag, 0));
}

TEST(NaiveDownsample, OtherGridsArePassedRefusedOrDroppedWithAWarning) {
  const MediumPtr fine = test::randomMedium(16);
  fine->source = "in.vdb";
  auto table = test::namedGridLike(*fine, "phase_table");
  table->tree().setValue(Coord(3, 0, 0), 0.08f);
  auto notes = test::namedGridLike(*fine, "temperature");
  // "lobes" is not a lobe grid of the contract: unknown, so dropped with a warning.
  auto lobes = test::namedGridLike(*fine, "lobes");
  fine->other_grids = {table, notes, lobes};
  const DownsampleResult result = downsampleNaive(*fine, {2, SggxWeighting::Count});
  ASSERT_EQ(result.medium->other_grids.size(), 1u);
  const auto& passed = static_cast<const openvdb::FloatGrid&>(*result.medium->other_grids[0]);
  EXPECT_EQ(passed.getName(), "phase_table");
  EXPECT_EQ(passed.tree().getValue(Coord(3, 0, 0)), 0.08f) << "the table is not spatial: copied as is";
  EXPECT_EQ(passed.transform(), result.medium->transform());
  ASSERT_EQ(result.warnings.size(), 2u);
  EXPECT_NE(result.warnings[0].find("temperature"), std::string::npos);
  EXPECT_NE(result.warnings[1].find("lobes"), std::string::npos);

  auto lobe = openvdb::Vec3SGrid::create();
  lobe->setName("lobe0_diag");
  fine->other_grids = {lobe};
  try {
    downsampleNaive(*fine, {2, SggxWeighting::Count});
    FAIL() << "multi-lobe grids cannot be averaged naively";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("in.vdb: grid 'lobe0_diag'"), std::string::npos) << e.what();
  }
}

TEST(NaiveDownsample, RefusesNonLinearTransforms) {
  const MediumPtr fine = test::randomMedium(16);
  fine->density->setTransform(openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(16)), 0.5, 2, 1));
  EXPECT_THROW(downsampleNaive(*fine, {2, SggxWeighting::Count}), MediumError);
}

}  // namespace
}  // namespace vdbappear
