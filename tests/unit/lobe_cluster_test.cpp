// Multi-lobe downsampling of whole media (§5, §6.2 of the downsampling paper): K-means, voxel
// clustering, lobe ordering (Eq. 13), and the invariants of Eq. (10)-(11) over random media and the twill.
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_block.h"
#include "libvdbappear/lobes/lobe_order.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/math/kmeans.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <fmt/format.h>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::Vec3s;


template <typename GridT>
typename GridT::ConstPtr gridNamed(const Medium& medium, const std::string& name) {
  for (const auto& grid : medium.other_grids)
    if (grid->getName() == name) return openvdb::gridConstPtrCast<GridT>(grid);
  return nullptr;
}

int intMetadata(const Medium& medium, const std::string& name) {
  const auto meta = medium.metadata.getMetadata<openvdb::Int32Metadata>(name);
  return meta ? meta->value() : -1;
}

// --- K-means -------------------------------------------------------------------------------------

TEST(KMeans, FindsSeparatedGroupsAndTheirWeightedMeans) {
  const std::vector<Vec3> points{{0, 0, 0}, {0.1, 0, 0}, {5, 5, 5}, {5, 5.2, 5}, {5, 5, 5.1}};
  const std::vector<double> weights{1, 3, 1, 1, 2};
  RandomStream rng(7, {});
  const KMeansResult<Vec3> result = kMeans(points, weights, 2, rng);
  ASSERT_EQ(result.centres.size(), 2u);
  const int a = result.cluster[0], b = result.cluster[2];
  EXPECT_NE(a, b);
  EXPECT_EQ(result.cluster[1], a);
  EXPECT_EQ(result.cluster[3], b);
  EXPECT_EQ(result.cluster[4], b);
  EXPECT_LT((result.centres[a] - Vec3(0.075, 0, 0)).norm(), 1e-12);
  EXPECT_LT((result.centres[b] - Vec3(5, 5.05, 5.05)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(result.weight[a], 4);
  EXPECT_DOUBLE_EQ(result.weight[b], 4);
}

TEST(KMeans, GivesFewerClustersThanDistinctPoints) {
  const std::vector<Vec3> points{{1, 2, 3}, {1, 2, 3}, {4, 5, 6}};
  RandomStream rng(1, {});
  const KMeansResult<Vec3> result = kMeans(points, {1, 1, 1}, 5, rng);
  EXPECT_EQ(result.centres.size(), 2u);
  for (int c : result.cluster) EXPECT_TRUE(c == 0 || c == 1);
}

// --- Lobe ordering (Eq. 13) -----------------------------------------------------------------------

TEST(LobeOrder, RecoversAPermutationOfTheReferenceLobes) {
  const std::vector<Mat3> S{Sggx::fiberMatrix(Vec3(1, 0, 0), 0.2), Sggx::fiberMatrix(Vec3(0, 1, 0), 0.3),
                            Sggx::surfaceMatrix(Vec3(0, 0, 1), 0.4)};
  std::vector<NdfSamples> reference;
  for (const Mat3& s : S) reference.push_back(sampleNdf(s));
  // The voxel holds slightly perturbed lobes in the order (2, 0, 1).
  const Mat3 tilt = Sggx::fiberMatrix(Vec3(1, 0.1, 0), 0.2);
  const std::vector<NdfSamples> lobes{sampleNdf(Sggx::surfaceMatrix(Vec3(0.1, 0, 1), 0.4)), sampleNdf(tilt),
                                      sampleNdf(Sggx::fiberMatrix(Vec3(0.1, 1, 0), 0.3))};
  EXPECT_EQ(matchLobeSlots(reference, lobes), (std::vector<int>{2, 0, 1}));
  EXPECT_EQ(matchLobeSlots(reference, reference), (std::vector<int>{0, 1, 2}));
  // Fewer lobes than the reference take the slots they match best.
  EXPECT_EQ(matchLobeSlots(reference, {lobes[0]}), (std::vector<int>{2}));
  EXPECT_EQ(matchLobeSlots(reference, {lobes[2], lobes[1]}), (std::vector<int>{1, 0}));
  EXPECT_THROW(matchLobeSlots({reference[0]}, lobes), std::invalid_argument);
}

// --- Voxel clustering (§6.2) ----------------------------------------------------------------------

TEST(VoxelClustering, SplitsAlbedoGroupsAndLabelsThemByIncreasingAlbedo) {
  std::vector<Vec3> albedo;
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < 300; ++i) {
    const double shade = (i % 3) * 0.4 + 0.01 * (i % 7);  // three groups: ~0, ~0.4, ~0.8
    albedo.push_back(Vec3(shade, shade, 0.5));
    keys.push_back(std::uint64_t(i));
  }
  const VoxelClustering clustering = clusterVoxels(albedo, keys, {3, 0.0, 1});
  ASSERT_EQ(clustering.centres.size(), 3u);
  for (int i = 0; i < 300; ++i) EXPECT_EQ(clustering.cluster[i], i % 3) << i;
  EXPECT_LT(clustering.centres[0].sum(), clustering.centres[1].sum());
  EXPECT_LT(clustering.centres[1].sum(), clustering.centres[2].sum());

  // One cluster: everything in cluster 0; more clusters than distinct albedos: fewer come out.
  const VoxelClustering one = clusterVoxels(albedo, keys, {1, 0.0, 1});
  for (int c : one.cluster) EXPECT_EQ(c, 0);
  const VoxelClustering few = clusterVoxels(std::vector<Vec3>(10, Vec3(0.5, 0.5, 0.5)), std::vector<std::uint64_t>(10, 0), {4, 0.0, 1});
  EXPECT_EQ(few.centres.size(), 1u);
}

// Jitter blurs the boundary between clusters of a smooth albedo ramp (Fig. 12): without it the
// ramp splits at one place; with it, voxels near the boundary mix. The jitter of a voxel depends on
// its key alone, so shuffling the voxels does not change anyone's cluster.
TEST(VoxelClustering, JitterBlursTheBoundaryOfARampAndIsKeyedPerVoxel) {
  const int n = 1000;
  std::vector<Vec3> ramp;
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < n; ++i) {
    ramp.push_back(Vec3::Constant(double(i) / n));
    keys.push_back(std::uint64_t(i) * 7919);
  }
  auto changes = [&](const std::vector<int>& cluster) {
    int count = 0;
    for (int i = 1; i < n; ++i) count += cluster[i] != cluster[i - 1];
    return count;
  };
  const VoxelClustering sharp = clusterVoxels(ramp, keys, {2, 0.0, 3});
  const VoxelClustering jittered = clusterVoxels(ramp, keys, {2, 0.05, 3});
  EXPECT_EQ(changes(sharp.cluster), 1);
  EXPECT_GT(changes(jittered.cluster), 5);

  std::vector<Vec3> reversed(ramp.rbegin(), ramp.rend());
  std::vector<std::uint64_t> reversed_keys(keys.rbegin(), keys.rend());
  const VoxelClustering shuffled = clusterVoxels(reversed, reversed_keys, {2, 0.05, 3});
  for (int i = 0; i < n; ++i) EXPECT_EQ(shuffled.cluster[n - 1 - i], jittered.cluster[i]) << i;
}

// --- Whole media ---------------------------------------------------------------------------------

// Every invariant of the written multi-lobe medium against the naive one: base grids identical to
// downsampleNaive with count weighting; per voxel sum_j fraction = 1, sum_j fraction S_j = naive S
// (Eq. 5, 10), sum_j W_j = naive albedo and W_j = albedo fraction_j (Eq. 11), every lobe S SPD,
// cluster ids in 0..K-1 and metadata matching.
void expectInvariants(const Medium& fine, const MultiLobeResult& result, int factor) {
  const Medium& out = *result.medium;
  const MediumPtr naive = downsampleNaive(fine, {factor, SggxWeighting::Count}).medium;
  EXPECT_TRUE(test::gridsMatch(*naive->density, *out.density, 0));
  ASSERT_EQ(bool(naive->albedo), bool(out.albedo));
  if (naive->albedo) EXPECT_TRUE(test::gridsMatch(*naive->albedo, *out.albedo, 0));
  EXPECT_TRUE(test::gridsMatch(*naive->sggx_diag, *out.sggx_diag, 0));
  EXPECT_TRUE(test::gridsMatch(*naive->sggx_offdiag, *out.sggx_offdiag, 0));
  const int m = result.lobe_count, K = int(result.clusters.size());
  EXPECT_EQ(intMetadata(out, "lobe_count"), m);
  EXPECT_EQ(intMetadata(out, "cluster_count"), K);
  ASSERT_FALSE(gridNamed<openvdb::Vec3SGrid>(out, fmt::format("lobe{}_weight", m)));
  const auto cluster = gridNamed<openvdb::Int32Grid>(out, "cluster");
  ASSERT_TRUE(cluster);
  EXPECT_TRUE(cluster->tree().hasSameTopology(out.density->tree()));

  struct Slot {
    openvdb::Vec3SGrid::ConstAccessor diag, offdiag, weight;
    openvdb::FloatGrid::ConstAccessor fraction;
  };
  std::vector<Slot> slots;
  for (int j = 0; j < m; ++j) {
    auto get3 = [&](const char* what) { return gridNamed<openvdb::Vec3SGrid>(out, fmt::format("lobe{}_{}", j, what)); };
    const auto fraction = gridNamed<openvdb::FloatGrid>(out, fmt::format("lobe{}_fraction", j));
    ASSERT_TRUE(get3("diag") && get3("offdiag") && get3("weight") && fraction) << "lobe " << j;
    slots.push_back({get3("diag")->getConstAccessor(), get3("offdiag")->getConstAccessor(),
                     get3("weight")->getConstAccessor(), fraction->getConstAccessor()});
  }
  const auto no_albedo = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));  // the contract's default
  auto albedo = (naive->albedo ? naive->albedo : no_albedo)->getConstAccessor();
  auto diag = naive->sggx_diag->getConstAccessor();
  auto offdiag = naive->sggx_offdiag->getConstAccessor();
  auto ids = cluster->getConstAccessor();
  std::uint64_t voxels = 0;
  for (auto voxel = naive->density->cbeginValueOn(); voxel; ++voxel) {
    const Coord ijk = voxel.getCoord();
    const Vec3 a = toVec3(albedo.getValue(ijk));
    double fraction_sum = 0;
    Mat3 S_sum = Mat3::Zero();
    Vec3 W_sum = Vec3::Zero();
    int lobes = 0;
    for (Slot& slot : slots) {
      float fraction = 0;
      const bool on = slot.fraction.probeValue(ijk, fraction);
      ASSERT_EQ(on, slot.weight.isValueOn(ijk)) << ijk;
      ASSERT_EQ(on, slot.diag.isValueOn(ijk)) << ijk;
      ASSERT_EQ(on, slot.offdiag.isValueOn(ijk)) << ijk;
      if (!on) continue;
      ++lobes;
      const Vec3 d = toVec3(slot.diag.getValue(ijk)), o = toVec3(slot.offdiag.getValue(ijk));
      EXPECT_TRUE(isPositiveDefinite(d, o)) << ijk;
      EXPECT_GT(fraction, 0) << ijk;
      const Vec3 W = toVec3(slot.weight.getValue(ijk));
      EXPECT_LT((W - a * double(fraction)).norm(), 1e-6) << ijk;  // Eq. (11)
      fraction_sum += fraction;
      S_sum += double(fraction) * sggxMatrix(d, o);
      W_sum += W;
    }
    ASSERT_GE(lobes, 1) << ijk;
    EXPECT_NEAR(fraction_sum, 1.0, 1e-6) << ijk;
    const Mat3 S_naive = sggxMatrix(toVec3(diag.getValue(ijk)), toVec3(offdiag.getValue(ijk)));
    EXPECT_LT((S_sum - S_naive).cwiseAbs().maxCoeff(), 2e-6 * (1 + S_naive.cwiseAbs().maxCoeff())) << ijk;
    EXPECT_LT((W_sum - a).cwiseAbs().maxCoeff(), 2e-6) << ijk;
    int id = -1;
    ASSERT_TRUE(ids.probeValue(ijk, id)) << ijk;
    EXPECT_GE(id, 0);
    EXPECT_LT(id, K);
    ++voxels;
  }
  EXPECT_EQ(voxels, result.statistics.voxels);
  std::uint64_t by_count = 0;
  for (std::uint64_t n : result.statistics.voxels_with_lobes) by_count += n;
  EXPECT_EQ(by_count, voxels);
}

TEST(MultiLobeDownsample, InvariantsOnRandomMedia) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const MediumPtr fine = test::randomMedium(32, seed);
    for (int factor : {2, 3}) {
      MultiLobeOptions options;
      options.factor = factor;
      options.clustering = {int(seed + 1), 0.02, seed};
      SCOPED_TRACE(fmt::format("seed {} factor {}", seed, factor));
      const MultiLobeResult result = downsampleMultiLobe(*fine, options);
      expectInvariants(*fine, result, factor);
      EXPECT_EQ(int(result.clusters.size()), options.clustering.clusters);
      EXPECT_GE(result.lobe_count, 2);  // random S: clusters of children help somewhere
    }
  }
}

TEST(MultiLobeDownsample, InvariantsOnTheTwillWithForcedLobes) {
  WeaveParams params;
  params.resolution = 64;
  params.yarns = 2;
  const MediumPtr fine = makeWeave(params);
  for (int lobes : {1, 2, 3}) {
    MultiLobeOptions options;
    options.factor = 4;
    options.fit.forced_lobes = lobes;
    options.clustering.clusters = 2;
    SCOPED_TRACE(fmt::format("{} lobes", lobes));
    const MultiLobeResult result = downsampleMultiLobe(*fine, options);
    expectInvariants(*fine, result, 4);
    EXPECT_EQ(result.lobe_count, lobes);
    EXPECT_EQ(result.clusters.size(), 2u);  // warp and weft colours
  }
}

// A hand-made medium whose voxels hold fibres along x and y in different proportions, so that the
// fits' own order (by decreasing fraction) differs between voxels: after Eq. (13) every voxel's
// lobe 0 has the reference's shape. Coarse voxel (c, 0, 0) holds 64 children: x_fibres[c] along x,
// the rest along y; the reference (the densest two-lobe voxel) is voxel 1, mostly y. Voxel 3 holds
// x fibres only: its one lobe goes to slot 1, where the reference keeps its x fibres, and slot 0
// stays empty there.
TEST(MultiLobeDownsample, LobeOrderFollowsTheReferenceVoxel) {
  const int F = 4, x_fibres[4] = {48, 16, 40, 64};
  const float density[4] = {1, 5, 2, 1};
  const MediumPtr fine = makeEmptyMedium({true, true, false}, openvdb::math::Transform::createLinearTransform(0.1));
  auto rho = fine->density->getAccessor();
  auto d = fine->sggx_diag->getAccessor();
  auto o = fine->sggx_offdiag->getAccessor();
  auto a = fine->albedo->getAccessor();
  const Mat3 along_x = Sggx::fiberMatrix(Vec3(1, 0, 0), 0.1), along_y = Sggx::fiberMatrix(Vec3(0, 1, 0), 0.1);
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < F * F * F; ++k) {
      const Coord ijk(c * F + k / 16, (k / 4) % 4, k % 4);
      const Mat3& S = k < x_fibres[c] ? along_x : along_y;
      rho.setValue(ijk, density[c]);
      d.setValue(ijk, toVec3s(sggxDiagonal(S)));
      o.setValue(ijk, toVec3s(sggxOffDiagonal(S)));
      a.setValue(ijk, Vec3s(0.5f));
    }
  MultiLobeOptions options;
  options.factor = F;
  options.fit.forced_lobes = 2;
  const MultiLobeResult result = downsampleMultiLobe(*fine, options);
  expectInvariants(*fine, result, F);
  ASSERT_EQ(result.clusters.size(), 1u);
  EXPECT_EQ(result.clusters[0].reference, (std::array<int, 3>{1, 0, 0}));
  const auto lobe0 = gridNamed<openvdb::Vec3SGrid>(*result.medium, "lobe0_diag");
  const auto fraction0 = gridNamed<openvdb::FloatGrid>(*result.medium, "lobe0_fraction");
  const auto lobe1 = gridNamed<openvdb::Vec3SGrid>(*result.medium, "lobe1_diag");
  for (int c = 0; c < 3; ++c) {
    const Vec3s S = lobe0->tree().getValue(Coord(c, 0, 0));
    EXPECT_LT(S.y(), S.x()) << "voxel " << c << ": lobe 0 should be the y fibres (small S_yy)";
    EXPECT_NEAR(fraction0->tree().getValue(Coord(c, 0, 0)), 1 - x_fibres[c] / 64.0, 1e-6) << "voxel " << c;
  }
  EXPECT_FALSE(fraction0->tree().isValueOn(Coord(3, 0, 0)));
  ASSERT_TRUE(lobe1->tree().isValueOn(Coord(3, 0, 0)));
  EXPECT_LT(lobe1->tree().getValue(Coord(3, 0, 0)).x(), 0.1f) << "voxel 3: its x fibres in slot 1";
}

// Media without an albedo grid (albedo 1), and more clusters asked for than distinct albedos.
TEST(MultiLobeDownsample, MediumWithoutAlbedoAndTooManyClusters) {
  RandomMediumParams params;
  params.extent = 24;
  params.albedo = false;
  const MediumPtr fine = makeRandomMedium(params);
  MultiLobeOptions options;
  options.clustering.clusters = 3;
  const MultiLobeResult result = downsampleMultiLobe(*fine, options);
  expectInvariants(*fine, result, options.factor);
  EXPECT_EQ(result.clusters.size(), 1u);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("3 clusters asked for, 1 made: the voxels hold only 1 distinct albedos"),
            std::string::npos)
      << result.warnings[0];
}

// A medium without SGGX grids has nothing to fit.
TEST(MultiLobeDownsample, RefusesAMediumWithoutSggx) {
  RandomMediumParams params;
  params.extent = 16;
  params.sggx = false;
  EXPECT_THROW(downsampleMultiLobe(*makeRandomMedium(params), {}), MediumError);
}

TEST(MultiLobeDownsample, SameOutputForAnyThreadCount) {
  const MediumPtr fine = test::randomMedium(32, 5);
  MultiLobeOptions options;
  options.factor = 2;
  options.clustering = {3, 0.05, 9};
  MultiLobeResult one, many;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = downsampleMultiLobe(*fine, options);
  }
  many = downsampleMultiLobe(*fine, options);
  ASSERT_EQ(one.lobe_count, many.lobe_count);
  ASSERT_EQ(one.medium->other_grids.size(), many.medium->other_grids.size());
  for (std::size_t g = 0; g < one.medium->other_grids.size(); ++g) {
    const auto& a = one.medium->other_grids[g];
    const auto& b = many.medium->other_grids[g];
    SCOPED_TRACE(a->getName());
    if (auto fa = openvdb::gridPtrCast<openvdb::FloatGrid>(a)) {
      EXPECT_TRUE(test::gridsMatch(*fa, *openvdb::gridPtrCast<openvdb::FloatGrid>(b), 0));
    } else if (auto va = openvdb::gridPtrCast<openvdb::Vec3SGrid>(a)) {
      EXPECT_TRUE(test::gridsMatch(*va, *openvdb::gridPtrCast<openvdb::Vec3SGrid>(b), 0));
    } else {
      auto ia = openvdb::gridPtrCast<openvdb::Int32Grid>(a), ib = openvdb::gridPtrCast<openvdb::Int32Grid>(b);
      ASSERT_TRUE(ia && ib);
      EXPECT_TRUE(ia->tree().hasSameTopology(ib->tree()));
      auto acc = ib->getConstAccessor();
      for (auto v = ia->cbeginValueOn(); v; ++v) EXPECT_EQ(*v, acc.getValue(v.getCoord()));
    }
  }
  for (std::size_t m = 0; m < one.statistics.squared_error.size(); ++m)
    EXPECT_EQ(one.statistics.squared_error[m], many.statistics.squared_error[m]);
}

// The §8.1 rule on a whole medium's errors: add a lobe while it at least halves the error.
TEST(MultiLobeDownsample, WholeMediumRule) {
  LobeFitStatistics s;
  s.squared_target = 100;
  s.squared_error = {16, 3.9, 1.2};  // errors 4, 1.97, 1.10: 2 halves 1, 3 does not halve 2
  EXPECT_EQ(s.ruleLobeCount(0.5), 2);
  EXPECT_DOUBLE_EQ(s.relativeError(1), 0.4);
  EXPECT_EQ(s.ruleLobeCount(0.6), 3);
  EXPECT_EQ(s.ruleLobeCount(0.4), 1);
  s.squared_error = {0, 0, 0};
  EXPECT_EQ(s.ruleLobeCount(0.5), 1);
}

TEST(MultiLobeDownsample, RejectsOptionsOutOfRangeAndLobeInput) {
  const MediumPtr fine = test::randomMedium(16, 1);
  MultiLobeOptions options;
  options.fit.max_lobes = kMaxOrderedLobes + 1;
  EXPECT_THROW(downsampleMultiLobe(*fine, options), std::invalid_argument);
  options.fit.max_lobes = 3;
  options.clustering.jitter = -1;
  EXPECT_THROW(downsampleMultiLobe(*fine, options), std::invalid_argument);
  options.clustering.jitter = 0;
  const MultiLobeResult once = downsampleMultiLobe(*fine, options);
  EXPECT_THROW(downsampleMultiLobe(*once.medium, options), MediumError);  // already multi-lobe
}

}  // namespace
}  // namespace vdbappear
