// Naive downsampling slab by slab (downsample/streamed_downsample.h, docs/scaling.md §5) against
// the whole medium read at once: the same grids, bit for bit, on media of every kind read in as many
// slabs as the smallest budget allows; and the reader's refusals.
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/downsample/streamed_downsample.h"
#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/procedural/hairy_ball_medium.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/velvet_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/error.h"

#include "support/identical_media.h"
#include "support/medium_testing.h"
#include "support/render_testing.h"
#include "support/temp_dir.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using openvdb::Coord;

// Leaves of the voxel-indexed grids whose values are in memory (not yet read from their file).
std::size_t leavesInMemory(const Medium& medium) {
  std::size_t count = 0;
  for (const auto& grid : medium.grids()) {
    if (auto f = openvdb::gridConstPtrCast<openvdb::FloatGrid>(grid))
      for (auto leaf = f->tree().cbeginLeaf(); leaf; ++leaf) count += !leaf->buffer().isOutOfCore();
    else if (auto v = openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(grid))
      for (auto leaf = v->tree().cbeginLeaf(); leaf; ++leaf) count += !leaf->buffer().isOutOfCore();
  }
  return count;
}

// The resident kB of this process's mappings of files whose name holds `name` (/proc/self/smaps).
std::uint64_t residentKbOfMappings(const std::string& name) {
  std::ifstream smaps("/proc/self/smaps");
  std::uint64_t kb = 0;
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    if (!line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) && line.find('-') < line.find(' '))
      inside = line.find(name) != std::string::npos;  // a mapping's first line
    else if (inside && line.rfind("Rss:", 0) == 0)
      kb += std::stoull(line.substr(4));
  }
  return kb;
}

std::vector<std::string> filesIn(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The smallest budget that reads `path`: what stays in memory and one band.
std::uint64_t smallestBudget(const std::string& path, int factor) {
  const MediumSlabs::Plan plan = MediumSlabs(path, {}).plan(8 * factor, ~std::uint64_t(0));
  return plan.resident_bytes + plan.largest_cell_bytes;
}

// Downsampled whole and in the most slabs the budget allows: identical; returns the slab count.
int expectStreamedEqualsInCore(const std::string& path, int factor, SggxWeighting weighting = SggxWeighting::Count) {
  const DownsampleOptions options{factor, weighting};
  const DownsampleResult whole = downsampleNaive(*readMedium(path), options);
  std::string why_not;
  const auto streamed = downsampleNaiveStreamed(path, {}, options, smallestBudget(path, factor), &why_not);
  EXPECT_TRUE(streamed) << path << ": " << why_not;
  if (!streamed) return 0;
  EXPECT_EQ(leavesInMemory(*streamed->result.medium), 0u) << path << ": the coarse slabs' values wait on disk";
  EXPECT_TRUE(test::identicalMedia(*whole.medium, *streamed->result.medium)) << path << ", factor " << factor;
  EXPECT_EQ(whole.warnings, streamed->result.warnings) << path;
  return streamed->slabs;
}

TEST(StreamedDownsample, EveryGoldenMediumIsDownsampledBitForBitInSlabs) {
  for (const char* name : {"cube8", "slab8", "sphere8", "cloud16", "twill24", "velvet16", "hairy-ball16", "exemplars8"})
    for (const int factor : {2, 3}) {
      const std::string path = std::string(GOLDEN_DIR) + "/" + name + ".vdb";
      expectStreamedEqualsInCore(path, factor);
      expectStreamedEqualsInCore(path, factor, SggxWeighting::Density);
    }
}

// Negative and odd index ranges, hg_g, many slabs; emission and blackbody light, made into the
// coarse emission slab by slab; a medium smaller than one slab.
TEST(StreamedDownsample, NegativeRangesEmissionAndOneSlab) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 53;  // -26 .. 26: odd, across zero
  params.hg_g = true;
  params.seed = 3;
  MediumPtr medium = makeRandomMedium(params);
  auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*medium, grid_names::kEmission, openvdb::Vec3s(0.0f));
  auto temperature = test::namedGridLike<openvdb::FloatGrid>(*medium, grid_names::kBlackbodyTemperature, 0.0f);
  test::TestRandom random(4);
  for (auto v = openvdb::CoordBBox(Coord(-30), Coord(29)).begin(); v; ++v) {
    if (random.uniform() < 0.05) emission->tree().setValueOn(*v, openvdb::Vec3s(float(random.uniform()), 0.5f, 0.25f));
    if (random.uniform() < 0.05) temperature->tree().setValueOn(*v, float(3000 * random.uniform()));
  }
  medium->other_grids = {emission, temperature};
  const std::string path = dir.path("random.vdb");
  writeMedium(*medium, path, "test");
  EXPECT_GE(expectStreamedEqualsInCore(path, 2), 4) << "many slabs";
  EXPECT_GE(expectStreamedEqualsInCore(path, 5), 2);
  EXPECT_EQ(expectStreamedEqualsInCore(std::string(GOLDEN_DIR) + "/cube8.vdb", 8), 1) << "smaller than one slab";
  // Bands cut along y and z into cells where one band exceeds the budget (io/medium_slabs.h).
  params.extent = 24;
  writeMedium(*test::spreadCopies(*makeRandomMedium(params), {Coord(0, -300, -300), Coord(5, -300, 10), Coord(0, 0, 0),
                                                              Coord(0, 140, 150), Coord(2, 140, 300), Coord(0, 400, -150)}),
              dir.path("spread.vdb"), "test");
  EXPECT_GE(expectStreamedEqualsInCore(dir.path("spread.vdb"), 2), 6);
  EXPECT_GE(expectStreamedEqualsInCore(dir.path("spread.vdb"), 3), 6);
}

// The coarse slabs wait on scratch files beside the output, removed as soon as they are mapped, and
// the write reads one leaf at a time: what it writes is what the whole read writes; the written
// medium's leaves stay on disk; nothing is left in the folder but the files asked for.
TEST(StreamedDownsample, TheCoarseSlabsWaitOnDiskAndAreWrittenLeafByLeaf) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 40;
  params.hg_g = true;
  params.seed = 5;
  writeMedium(*makeRandomMedium(params), dir.path("in.vdb"), "test");
  const DownsampleOptions options{2, SggxWeighting::Count};
  writeMedium(*downsampleNaive(*readMedium(dir.path("in.vdb")), options).medium, dir.path("whole.vdb"), "test");

  std::string why_not;
  const std::string out = dir.path("slabs.vdb");
  const auto streamed = downsampleNaiveStreamed(dir.path("in.vdb"), {}, options, smallestBudget(dir.path("in.vdb"), 2),
                                                &why_not, nullptr, out);
  ASSERT_TRUE(streamed) << why_not;
  EXPECT_GE(streamed->slabs, 3);
  EXPECT_EQ(filesIn(dir.path("")), (std::vector<std::string>{"in.vdb", "whole.vdb"})) << "no scratch file is left";
  // The pages its topology's reading faulted in are given back: a few thousand small parts held 1.1
  // GB of their files for a budget of 0.16 GB before (the 1024^3 twill).
  EXPECT_EQ(residentKbOfMappings(".vdbappear-part.tmp."), 0u) << "the scratch files' pages are given back";
  const std::size_t leaves = streamed->result.medium->density->tree().leafCount();
  EXPECT_EQ(leavesInMemory(*streamed->result.medium), 0u);
  EXPECT_TRUE(isValidatedInParts(*streamed->result.medium));
  writeMedium(*streamed->result.medium, out, "test");
  EXPECT_EQ(leavesInMemory(*streamed->result.medium), 0u) << "written from copies, a leaf at a time";
  EXPECT_EQ(streamed->result.medium->density->tree().leafCount(), leaves);
  EXPECT_TRUE(test::identicalMedia(*readMedium(dir.path("whole.vdb")), *readMedium(out)));
  EXPECT_EQ(filesIn(dir.path("")), (std::vector<std::string>{"in.vdb", "slabs.vdb", "whole.vdb"}));
  // Byte for byte the file OpenVDB's writer writes (its table of leaf sizes included, computed here
  // when each slab was spilled), but for the header's random UUID (36 bytes from byte 21).
  const std::string whole_bytes = test::readFileBytes(dir.path("whole.vdb")), slab_bytes = test::readFileBytes(out);
  ASSERT_EQ(whole_bytes.size(), slab_bytes.size());
  std::size_t differ = 0;
  while (differ < whole_bytes.size() && (whole_bytes[differ] == slab_bytes[differ] || (differ >= 21 && differ < 57))) ++differ;
  EXPECT_EQ(differ, whole_bytes.size()) << "the files differ from byte " << differ << ": '"
                                        << whole_bytes.substr(differ, 40) << "' against '" << slab_bytes.substr(differ, 40) << "'";
}

// Made under a budget that sends it to disk in many slabs, a twill is the twill made whole, grid for
// grid and bit for bit, its values unread until written, and written to a file read back the same;
// under a large budget it is made whole in memory.
TEST(StreamedGeneration, ATwillMadeInSlabsIsTheTwillMadeWhole) {
  test::TempDir dir;
  WeaveParams params;
  params.resolution = 48;
  params.layers = 2;
  const MediumPtr whole = makeWeave(params);
  writeMedium(*whole, dir.path("whole.vdb"), "test");
  const std::uint64_t data_bytes = whole->density->tree().leafCount() * 20 * 512;  // density, albedo, S
  params.memory = {data_bytes / 4, dir.path("slabs.vdb")};  // in memory until data/16, slabs of data/32
  const MediumPtr slabs = makeWeave(params);
  EXPECT_TRUE(isValidatedInParts(*slabs));
  EXPECT_EQ(leavesInMemory(*slabs), 0u);
  EXPECT_TRUE(test::identicalMedia(*whole, *slabs));
  writeMedium(*slabs, dir.path("slabs.vdb"), "test");
  EXPECT_TRUE(test::identicalMedia(*readMedium(dir.path("whole.vdb")), *readMedium(dir.path("slabs.vdb"))));
  EXPECT_EQ(filesIn(dir.path("")), (std::vector<std::string>{"slabs.vdb", "whole.vdb"}));

  params.memory.budget_bytes = std::uint64_t(1) << 32;
  const MediumPtr roomy = makeWeave(params);
  EXPECT_FALSE(isValidatedInParts(*roomy)) << "made whole in memory";
  EXPECT_TRUE(test::identicalMedia(*whole, *roomy));
}

// A procedural kind made whole and made in slabs on disk under `memory`: the same grids, bit for bit.
template <typename ParamsT>
void expectMadeInSlabsAsWhole(ParamsT params, MediumPtr (*make)(const ParamsT&), const FillMemory& memory) {
  const MediumPtr whole = make(params);
  params.memory = memory;
  const MediumPtr slabs = make(params);
  EXPECT_TRUE(isValidatedInParts(*slabs));
  EXPECT_TRUE(test::identicalMedia(*whole, *slabs));
}

// Velvet and the hairy ball (its index range centred on zero), made in slabs: the media made whole.
TEST(StreamedGeneration, VelvetAndHairyBallMadeInSlabsAreMadeWhole) {
  test::TempDir dir;
  const FillMemory small{std::uint64_t(1) << 20, dir.path("out.vdb")};  // slabs of 128 KB
  VelvetParams velvet;
  velvet.resolution = 32;
  expectMadeInSlabsAsWhole(velvet, makeVelvet, small);
  HairyBallParams ball;
  ball.resolution = 40;
  expectMadeInSlabsAsWhole(ball, makeHairyBall, small);
  EXPECT_TRUE(filesIn(dir.path("")).empty()) << "no scratch file is left";
}

// Refusals, as the whole read gives them: a budget too small for one slab names what it needs; an
// empty density; a truncated file names the grid; a file a preset maps is left to the whole read.
TEST(StreamedDownsample, RefusesWhatTheWholeReadRefusesAndNamesTheBudget) {
  const std::string twill = std::string(GOLDEN_DIR) + "/twill24.vdb";
  try {
    downsampleNaiveStreamed(twill, {}, {2, SggxWeighting::Count}, 1000, nullptr);
    ADD_FAILURE() << "a budget of 1000 bytes was accepted";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("a memory budget of 1e-06 GB is too small: one piece of 16 x 128 x 128 voxels needs"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("(--memory "), std::string::npos) << e.what();
  }

  test::TempDir dir;
  auto empty = test::cube(4, 1.0, 0.0f, 0.5f);
  test::writeRawVdb(dir.path("empty.vdb"), test::copyGrids(*empty));
  EXPECT_EQ(test::readMediumError(dir.path("empty.vdb")), dir.path("empty.vdb") + ": grid 'density': empty grid (no voxel with density > 0)");
  try {
    downsampleNaiveStreamed(dir.path("empty.vdb"), {}, {2, SggxWeighting::Count}, 1u << 30, nullptr);
    ADD_FAILURE() << "an empty medium was accepted";
  } catch (const MediumError& e) {
    EXPECT_EQ(std::string(e.what()), test::readMediumError(dir.path("empty.vdb")));
  }

  // Truncated anywhere: refused naming the file, as the whole read refuses it, never a result.
  for (const double keep : {0.25, 0.5, 0.75, 0.9, 0.99}) {
    const std::string cut = dir.path("cut.vdb");
    std::filesystem::remove(cut);
    std::filesystem::copy_file(twill, cut);
    std::filesystem::resize_file(cut, std::uintmax_t(double(std::filesystem::file_size(twill)) * keep));
    try {
      downsampleNaiveStreamed(cut, {}, {2, SggxWeighting::Count}, 1u << 30, nullptr);
      ADD_FAILURE() << "a file cut at " << keep << " was accepted";
    } catch (const MediumError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(cut + ": ", 0), 0u) << e.what();
    }
  }

  auto grey = test::cube(4, 1.0, 1.0f, 0.5f);
  auto colour = test::namedGridLike<openvdb::Vec3SGrid>(*grey, "Cd", openvdb::Vec3s(0.0f));
  colour->tree().setValueOn(Coord(1, 1, 1), openvdb::Vec3s(0.5f));
  test::writeRawVdb(dir.path("houdini.vdb"), {grey->density, colour});
  std::string why_not;
  EXPECT_FALSE(downsampleNaiveStreamed(dir.path("houdini.vdb"), {}, {2, SggxWeighting::Count}, 1u << 30, &why_not));
  EXPECT_EQ(why_not, "a preset maps its grids (--from none reads them as they are)");
}

}  // namespace
}  // namespace vdbappear
