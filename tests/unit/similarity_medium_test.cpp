// Media altered by the similarity relations (similarity/similarity_medium.h): per-voxel coefficients,
// one table per distinct phase function, the g quantisation bound, refusals.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/phase_tables.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/similarity/altered_coefficients.h"
#include "libvdbappear/similarity/legendre_moments.h"
#include "libvdbappear/similarity/similarity_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace vdbappear {
namespace {

// Few quantisation levels keep these tests fast (g spans (-0.9, 0.9): 1/100 of it per level).
MediumSimilarityOptions coarse() {
  MediumSimilarityOptions options;
  options.moment_tolerance = 0.025;
  return options;
}

MediumPtr randomHgMedium(std::uint64_t seed) {
  RandomMediumParams p;
  p.extent = 24;
  p.seed = seed;
  p.sggx = false;
  p.hg_g = true;
  return makeRandomMedium(p);
}

Rgb albedoAt(const Medium& m, const openvdb::Coord& ijk) {
  return m.albedo ? Rgb(toVec3(m.albedo->tree().getValue(ijk)).array()) : Rgb(1, 1, 1);
}

// Every voxel of a random medium with per-voxel g in (-0.9, 0.9): its table's g_q lies within the
// bound's reach, density* and albedo* follow alterCoefficients with that table's alpha, and the
// table's moments differ from those of the voxel's exact altered phase function by at most the
// bound / alpha (plus rounding).
TEST(SimilarityMedium, PerVoxelGIsQuantisedWithinTheMomentBound) {
  const MediumPtr input = randomHgMedium(3);
  MediumSimilarityOptions options;
  options.moment_tolerance = 5e-3;
  const MediumSimilarityResult r = alterMedium(*input, options);
  EXPECT_GT(r.g_levels, 0);
  EXPECT_LE(r.moment_tolerance, 5e-3);
  EXPECT_LE(r.max_moment_error, r.moment_tolerance);
  EXPECT_GT(r.max_moment_error, 0.5 * r.moment_tolerance) << "random g should come close to the bound";
  EXPECT_GT(r.tables.size(), 50u);
  const Medium& out = *r.medium;
  EXPECT_FALSE(out.hg_g);
  const auto ids = findOtherGrid<openvdb::Int32Grid>(out, grid_names::kPhaseId);
  ASSERT_TRUE(ids);
  const std::vector<std::vector<double>> tables = readPhaseTables(out);
  ASSERT_EQ(tables.size(), r.tables.size());

  std::uint64_t voxels = 0;
  double worst_moment = 0;
  auto density = out.density->getConstAccessor();
  auto id = ids->getConstAccessor();
  for (auto v = input->density->cbeginValueOn(); v; ++v) {
    if (!(*v > 0)) continue;
    ++voxels;
    const openvdb::Coord ijk = v.getCoord();
    const AlteredTable& t = r.tables.at(id.getValue(ijk));
    const double g = input->hg_g->tree().getValue(ijk);
    const AlteredCoefficients expected = alterCoefficients(*v, albedoAt(*input, ijk), t.phase.alpha, t.f1);
    ASSERT_NEAR(density.getValue(ijk), expected.density, 1e-5 * expected.density);
    ASSERT_LT((albedoAt(out, ijk) - expected.albedo).abs().maxCoeff(), 1e-6);
    const std::vector<double> exact = alteredMoments(henyeyGreensteinMoments(g, t.phase.order), t.phase.alpha);
    const std::vector<double> got = tableMoments(tables[id.getValue(ijk)], t.phase.order);
    for (int n = 0; n <= t.phase.order; ++n) worst_moment = std::max(worst_moment, std::abs(got[n] - exact[n]) * t.phase.alpha);
  }
  EXPECT_EQ(voxels, r.voxels);
  EXPECT_LE(worst_moment, r.moment_tolerance + 1e-6) << "stored tables are floats";
  std::uint64_t counted = 0;
  for (const AlteredTable& t : r.tables) counted += t.voxels;
  EXPECT_EQ(counted, r.voxels);
}

TEST(SimilarityMedium, ConstantGGivesOneTableAndNoIds) {
  auto input = test::randomMedium(16, 4);
  input->sggx_diag = input->sggx_offdiag = nullptr;
  input->metadata.insertMeta(metadata_names::kHgG, openvdb::FloatMetadata(0.9f));
  const MediumSimilarityResult r = alterMedium(*input, {});
  ASSERT_EQ(r.tables.size(), 1u);
  EXPECT_NEAR(r.tables[0].phase.alpha, 0.3, 1e-6);
  EXPECT_FALSE(findOtherGrid<openvdb::Int32Grid>(*r.medium, grid_names::kPhaseId));
  EXPECT_FALSE(hgGMetadata(r.medium->metadata));
  EXPECT_EQ(r.g_levels, 0);
  EXPECT_EQ(r.notes.size(), 1u);
}

// A medium with two tables and phase_id keeps its ids; each table is altered once.
TEST(SimilarityMedium, TablesAreAlteredOnceAndIdsKept) {
  auto input = test::randomMedium(16, 5);
  input->sggx_diag = input->sggx_offdiag = nullptr;
  setPhaseTables(*input, {tabulateHenyeyGreenstein(0.9, 720), tabulateHenyeyGreenstein(0.6, 720)});
  auto ids = test::namedGridLike<openvdb::Int32Grid>(*input, grid_names::kPhaseId, 0);
  for (auto v = input->density->cbeginValueOn(); v; ++v) ids->tree().setValueOn(v.getCoord(), v.getCoord().x() > 0 ? 1 : 0);
  input->other_grids.push_back(ids);
  const MediumSimilarityResult r = alterMedium(*input, {});
  ASSERT_EQ(r.tables.size(), 2u);
  EXPECT_EQ(findOtherGrid<openvdb::Int32Grid>(*r.medium, grid_names::kPhaseId), ids);
  EXPECT_GT(r.tables[0].voxels, 0u);
  EXPECT_GT(r.tables[1].voxels, 0u);
  const std::vector<std::vector<double>> out = readPhaseTables(*r.medium);
  for (int t = 0; t < 2; ++t) {
    const AlteredPhase& a = r.tables[t].phase;
    EXPECT_NEAR(a.alpha, t == 0 ? 0.3 : 0.4, 1e-3);
    const std::vector<double> expected = alteredMoments(tableMoments(normalisedTable(t == 0 ? tabulateHenyeyGreenstein(0.9, 720) : tabulateHenyeyGreenstein(0.6, 720)), a.order), a.alpha);
    const std::vector<double> got = tableMoments(out[t], a.order);
    for (int n = 0; n <= a.order; ++n) EXPECT_NEAR(got[n], expected[n], 1e-5) << "table " << t << " n " << n;
  }
}

TEST(SimilarityMedium, OutputIsTheSameForAnyThreadCount) {
  const MediumPtr input = randomHgMedium(6);
  std::vector<MediumPtr> outputs;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    outputs.push_back(alterMedium(*input, coarse()).medium);
  }
  EXPECT_TRUE(test::gridsMatch(*outputs[0]->density, *outputs[1]->density, 0.0));
  EXPECT_TRUE(test::gridsMatch(*outputs[0]->albedo, *outputs[1]->albedo, 0.0));
  EXPECT_TRUE(test::gridsMatch(*findOtherGrid<openvdb::Int32Grid>(*outputs[0], grid_names::kPhaseId),
                               *findOtherGrid<openvdb::Int32Grid>(*outputs[1], grid_names::kPhaseId), 0.0));
}

TEST(SimilarityMedium, WritesAMediumTheReaderAccepts) {
  const test::TempDir dir;
  const MediumSimilarityResult r = alterMedium(*randomHgMedium(7), coarse());
  writeMedium(*r.medium, dir.path("out.vdb"), "test");
  const MediumPtr back = readMedium(dir.path("out.vdb"));
  EXPECT_EQ(readPhaseTables(*back).size(), r.tables.size());
}

TEST(SimilarityMedium, RefusesSggxMedia) {
  const MediumPtr input = test::randomMedium(16, 8);
  try {
    alterMedium(*input, {});
    FAIL() << "expected a MediumError";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("grid 'sggx_diag'"), std::string::npos) << e.what();
  }
}

TEST(SimilarityMedium, RefusesPhaseIdsOutsideTheTables) {
  auto input = test::randomMedium(16, 9);
  input->sggx_diag = input->sggx_offdiag = nullptr;
  setPhaseTables(*input, {tabulateHenyeyGreenstein(0.9, 64)});
  auto ids = test::namedGridLike<openvdb::Int32Grid>(*input, grid_names::kPhaseId, 0);
  const openvdb::Coord bad = input->density->cbeginValueOn().getCoord();
  ids->tree().setValueOn(bad, 3);
  input->other_grids.push_back(ids);
  try {
    alterMedium(*input, {});
    FAIL() << "expected a MediumError";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("grid 'phase_id': table id 3 outside 0..0"), std::string::npos) << e.what();
  }
}

TEST(SimilarityMedium, RefusesAnAlphaTooSmallForSomeVoxel) {
  MediumSimilarityOptions options = coarse();
  options.phase.alpha = 0.3;  // g = -0.9 needs alpha >= 0.95
  EXPECT_THROW(alterMedium(*randomHgMedium(10), options), std::invalid_argument);
}

}  // namespace
}  // namespace vdbappear
