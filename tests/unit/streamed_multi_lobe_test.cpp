// vdb_lobe_cluster's reduction slab by slab (lobes/streamed_multi_lobe.h, docs/scaling.md §5)
// against the whole medium read at once: the same grids bit for bit (lobes, weights, clusters), the
// same clusters, references and fit statistics, on media of every kind read in as many slabs as the
// smallest budget allows; the stages' tree order; and the refusals.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/lobes/distinct_albedo_table.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/lobes/multi_lobe_stages.h"
#include "libvdbappear/lobes/streamed_multi_lobe.h"
#include "libvdbappear/math/kmeans.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/util/error.h"

#include "support/identical_media.h"
#include "support/medium_testing.h"
#include "support/render_testing.h"
#include "support/temp_dir.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

namespace vdbappear {
namespace {

using openvdb::Coord;

// The smallest budget that reads `path` for these options: what stays in memory and one band.
std::uint64_t smallestBudget(const std::string& path, const MultiLobeOptions& options) {
  const MediumSlabs::Plan plan =
      MediumSlabs(path, {}).plan(8 * options.factor, ~std::uint64_t(0), ~std::uint64_t(0), 4 * MultiLobeStages(options).slotCount() + 1);
  return plan.resident_bytes + plan.largest_cell_bytes;
}

void expectSameResult(const MultiLobeResult& whole, const MultiLobeResult& slabs, const std::string& what) {
  EXPECT_TRUE(test::identicalMedia(*whole.medium, *slabs.medium)) << what;
  EXPECT_EQ(whole.lobe_count, slabs.lobe_count) << what;
  EXPECT_EQ(whole.warnings, slabs.warnings) << what;
  ASSERT_EQ(whole.clusters.size(), slabs.clusters.size()) << what;
  for (std::size_t c = 0; c < whole.clusters.size(); ++c) {
    EXPECT_EQ(whole.clusters[c].albedo, slabs.clusters[c].albedo) << what << ", cluster " << c;
    EXPECT_EQ(whole.clusters[c].voxels, slabs.clusters[c].voxels) << what << ", cluster " << c;
    EXPECT_EQ(whole.clusters[c].reference, slabs.clusters[c].reference) << what << ", cluster " << c;
    EXPECT_EQ(whole.clusters[c].reference_lobes, slabs.clusters[c].reference_lobes) << what << ", cluster " << c;
  }
  const LobeFitStatistics &a = whole.statistics, &b = slabs.statistics;
  EXPECT_EQ(a.voxels, b.voxels) << what;
  EXPECT_EQ(a.voxels_exact_with_one_lobe, b.voxels_exact_with_one_lobe) << what;
  EXPECT_EQ(a.voxels_with_lobes, b.voxels_with_lobes) << what;
  EXPECT_EQ(a.squared_error, b.squared_error) << what << ": summed in the same order";
  EXPECT_EQ(a.squared_target, b.squared_target) << what;
}

// Reduced whole and in the most slabs the budget allows: identical; returns the slab count.
int expectStreamedEqualsInCore(const std::string& path, const MultiLobeOptions& options) {
  const std::string what = path + ", factor " + std::to_string(options.factor);
  const MultiLobeResult whole = downsampleMultiLobe(*readMedium(path), options);
  std::string why_not;
  const auto streamed = downsampleMultiLobeStreamed(path, {}, options, smallestBudget(path, options), &why_not);
  EXPECT_TRUE(streamed) << what << ": " << why_not;
  if (!streamed) return 0;
  EXPECT_TRUE(isValidatedInParts(*streamed->result.medium)) << what << ": the ordered slabs wait on disk";
  expectSameResult(whole, streamed->result, what);
  return streamed->slabs;
}

MultiLobeOptions lobeOptions(int factor, int forced_lobes, int clusters, double jitter = 0, std::uint64_t seed = 1) {
  MultiLobeOptions options;
  options.factor = factor;
  options.fit.forced_lobes = forced_lobes;
  options.clustering = {clusters, jitter, seed};
  return options;
}

TEST(StreamedMultiLobe, EveryGoldenMediumWithFlakesIsReducedBitForBitInSlabs) {
  for (const char* name : {"twill24", "velvet16", "hairy-ball16"})
    for (const int factor : {2, 3}) {
      const std::string path = std::string(GOLDEN_DIR) + "/" + name + ".vdb";
      expectStreamedEqualsInCore(path, lobeOptions(factor, 0, 3));
      expectStreamedEqualsInCore(path, lobeOptions(factor, 2, 2, 0.05, 7));  // jittered albedos
    }
}

// Negative and odd index ranges, hg_g, many slabs and many clusters; a medium smaller than one slab.
TEST(StreamedMultiLobe, NegativeRangesManySlabsAndOneSlab) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 53;  // -26 .. 26: odd, across zero
  params.hg_g = true;
  params.seed = 3;
  const std::string path = dir.path("random.vdb");
  writeMedium(*makeRandomMedium(params), path, "test");
  EXPECT_GE(expectStreamedEqualsInCore(path, lobeOptions(2, 0, 6)), 4) << "many slabs";
  EXPECT_GE(expectStreamedEqualsInCore(path, lobeOptions(2, 3, 4, 0.1, 2)), 4);
  EXPECT_GE(expectStreamedEqualsInCore(path, lobeOptions(5, 2, 3)), 2);
  const std::string twill = std::string(GOLDEN_DIR) + "/twill24.vdb";  // x = 0..23
  EXPECT_EQ(expectStreamedEqualsInCore(twill, lobeOptions(2, 0, 2)), 2);
  EXPECT_EQ(expectStreamedEqualsInCore(twill, lobeOptions(4, 0, 2)), 1) << "smaller than one slab";
}

// The clustering's input gathered part by part, in any split and order: the distinct albedos and
// counts of the whole (distinctPoints, what clusterVoxels clusters), with +0 and -0 one albedo.
TEST(StreamedMultiLobe, DistinctAlbedoTableGatheredInPartsIsTheWholes) {
  test::TestRandom random(11);
  std::vector<Vec3> all;
  for (int i = 0; i < 2000; ++i)  // few distinct values: many repeats
    all.push_back(Vec3(std::floor(random.uniform() * 5) / 4, std::floor(random.uniform() * 3) / 2, i % 7 == 0 ? 0.25 : 0.5));
  const DistinctPoints<Vec3> whole = distinctPoints(all);
  for (const int parts : {1, 2, 5, 17}) {
    DistinctAlbedoTable table;
    for (int p = parts - 1; p >= 0; --p) {  // the parts backwards
      std::vector<Vec3> part;
      for (std::size_t i = std::size_t(p); i < all.size(); i += std::size_t(parts)) part.push_back(all[i]);
      table.add(part);
    }
    EXPECT_EQ(table.albedo(), whole.point) << parts << " parts";
    EXPECT_EQ(table.voxels(), whole.count) << parts << " parts";
    for (std::size_t i = 0; i < all.size(); i += 97) EXPECT_EQ(table.find(all[i]), std::size_t(whole.of[i]));
  }
  DistinctAlbedoTable table;
  std::vector<Vec3> zeros = {clusteringInput(Vec3(-0.0, 0.5, 0.5), 1, {}), Vec3(0.0, 0.5, 0.5)};
  table.add(zeros);
  EXPECT_EQ(table.size(), 1u);
  EXPECT_FALSE(std::signbit(table.albedo()[0].x())) << "clusteringInput makes -0 +0";
  EXPECT_THROW(table.find(Vec3(0.1, 0.2, 0.3)), std::logic_error);
}

// A band larger than the budget allows is cut along y and z into cells (io/medium_slabs.h): the
// pieces together are still the whole read, bit for bit, for both streamed reductions.
TEST(StreamedMultiLobe, BandsCutAlongYAndZGiveTheWholeReadsResult) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 24;
  params.seed = 9;
  const MediumPtr blob = makeRandomMedium(params);
  const std::string path = dir.path("spread.vdb");
  writeMedium(*test::spreadCopies(*blob, {Coord(0, -300, -300), Coord(5, -300, 10), Coord(0, 0, 0), Coord(-3, 140, 0),
                                    Coord(0, 140, 150), Coord(2, 140, 300), Coord(0, 400, -150)}),
              path, "test");
  const MultiLobeOptions options = lobeOptions(2, 0, 3, 0.02, 4);
  const MediumSlabs::Plan plan = MediumSlabs(path, {}).plan(16, smallestBudget(path, options), ~std::uint64_t(0), 13);
  int cut = 0;
  for (const openvdb::CoordBBox& piece : plan.slabs) cut += piece.min().y() > Coord::min().y();
  EXPECT_GE(cut, 5) << "pieces cut along y (and z)";
  EXPECT_GE(expectStreamedEqualsInCore(path, options), 8);
}

// The references' tie-break ("first in tree order"): the order OpenVDB's iterators visit voxels in.
TEST(StreamedMultiLobe, TreeOrderIsTheOrderOfOpenVdbsIterators) {
  openvdb::FloatTree tree;
  const std::vector<Coord> voxels = {Coord(-5000, 3, 2), Coord(-1, -1, -1), Coord(0, 0, 0), Coord(0, 0, 9),
                                     Coord(0, 9, 0),     Coord(9, 0, 0),    Coord(7, 7, 7), Coord(127, 0, 0),
                                     Coord(128, -3, 0),  Coord(0, 4096, 0), Coord(4095, 4095, 4095), Coord(4096, -4096, 1)};
  for (const Coord& ijk : voxels) tree.setValueOn(ijk, 1.0f);
  std::vector<Coord> visited;
  for (auto v = tree.cbeginValueOn(); v; ++v) visited.push_back(v.getCoord());
  ASSERT_EQ(visited.size(), voxels.size());
  std::vector<Coord> sorted = voxels;
  std::sort(sorted.begin(), sorted.end(), beforeInTreeOrder);
  EXPECT_EQ(sorted, visited);
  std::sort(sorted.begin(), sorted.end());  // lexicographic: a different order (negative control)
  EXPECT_NE(sorted, visited);
}

// The parked slabs and the output's wait on scratch files removed as they are made: nothing is left
// in the folder but what was asked for, and the written file reads back as the whole read's.
TEST(StreamedMultiLobe, WritesWhatTheWholeReadWritesAndLeavesNoScratchFile) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 40;
  params.seed = 5;
  const std::string in = dir.path("in.vdb");
  writeMedium(*makeRandomMedium(params), in, "test");
  const MultiLobeOptions options = lobeOptions(2, 0, 3);
  writeMedium(*downsampleMultiLobe(*readMedium(in), options).medium, dir.path("whole.vdb"), "test");
  const std::string out = dir.path("slabs.vdb");
  auto streamed = downsampleMultiLobeStreamed(in, {}, options, smallestBudget(in, options), nullptr, nullptr, out);
  ASSERT_TRUE(streamed);
  EXPECT_GE(streamed->slabs, 3);
  EXPECT_GT(streamed->parked_bytes, 0u);
  writeMedium(*streamed->result.medium, out, "test");
  streamed.reset();
  EXPECT_TRUE(test::identicalMedia(*readMedium(dir.path("whole.vdb")), *readMedium(out)));
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path(""))) files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"in.vdb", "slabs.vdb", "whole.vdb"}));
}

std::string streamedError(const std::string& path, const MultiLobeOptions& options, std::uint64_t budget) {
  try {
    downsampleMultiLobeStreamed(path, {}, options, budget, nullptr);
  } catch (const MediumError& e) {
    return e.what();
  }
  return "";
}

// Refusals, as the whole read and downsampleMultiLobe give them.
TEST(StreamedMultiLobe, RefusesWhatTheWholeReadRefusesAndNamesTheBudget) {
  const std::string twill = std::string(GOLDEN_DIR) + "/twill24.vdb";
  const MultiLobeOptions options = lobeOptions(2, 2, 2);
  const std::string small = streamedError(twill, options, 1000);
  EXPECT_NE(small.find("a memory budget of 1e-06 GB is too small: one piece of 16 x 128 x 128 voxels needs"), std::string::npos)
      << small;
  EXPECT_NE(small.find("(--memory "), std::string::npos) << small;

  test::TempDir dir;
  auto empty = test::cube(4, 1.0, 0.0f, 0.5f);
  empty->sggx_diag = test::namedGridLike<openvdb::Vec3SGrid>(*empty, grid_names::kSggxDiag, openvdb::Vec3s(1.0f));
  empty->sggx_diag->tree().setValueOn(Coord(1), openvdb::Vec3s(0.5f));
  test::writeRawVdb(dir.path("empty.vdb"), test::copyGrids(*empty));
  EXPECT_EQ(streamedError(dir.path("empty.vdb"), options, 1u << 30), test::readMediumError(dir.path("empty.vdb")));

  const std::string cube = dir.path("cube.vdb");  // no SGGX grids: nothing to fit
  test::writeRawVdb(cube, test::copyGrids(*test::cube(4, 1.0, 1.0f, 0.5f)));
  std::string whole_error;
  try {
    downsampleMultiLobe(*readMedium(cube), options);
  } catch (const MediumError& e) {
    whole_error = e.what();
  }
  EXPECT_FALSE(whole_error.empty());
  EXPECT_EQ(streamedError(cube, options, 1u << 30), whole_error);

  const std::string lobes = dir.path("lobes.vdb");  // already multi-lobe
  writeMedium(*downsampleMultiLobe(*readMedium(twill), options).medium, lobes, "test");
  EXPECT_NE(streamedError(lobes, options, 1u << 30).find("the medium is already multi-lobe"), std::string::npos);

  for (const double keep : {0.25, 0.5, 0.75, 0.9, 0.99}) {  // truncated anywhere: refused naming the file
    const std::string cut = dir.path("cut.vdb");
    std::filesystem::remove(cut);
    std::filesystem::copy_file(twill, cut);
    std::filesystem::resize_file(cut, std::uintmax_t(double(std::filesystem::file_size(twill)) * keep));
    EXPECT_EQ(streamedError(cut, options, 1u << 30).rfind(cut + ": ", 0), 0u) << "cut at " << keep;
  }
}

}  // namespace
}  // namespace vdbappear
