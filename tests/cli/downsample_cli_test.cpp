// vdb_sggx_downsample from the command line: flags, errors, pipes, files.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/procedural/random_medium.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kDownsample;
using test::kMakeMedium;
using test::lineCount;
using test::quote;
using test::readFileBytes;
using test::runCommand;
using test::TempDir;

// A random medium file made by vdb_make_medium.
std::string makeRandomFile(const TempDir& dir, int res = 40, int seed = 3) {
  const std::string path = dir.path("in.vdb");
  const auto r = runCommand(kMakeMedium + " random --res " + std::to_string(res) + " --seed " + std::to_string(seed) +
                            " -o " + quote(path));
  EXPECT_EQ(r.status, 0) << r.err;
  return path;
}

TEST(DownsampleCli, HelpShowsUsageAndExamples) {
  const auto r = runCommand(kDownsample + " --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("Usage:"), std::string::npos);
  EXPECT_NE(r.out.find("--s-weight"), std::string::npos);
  EXPECT_NE(r.out.find("Examples:"), std::string::npos);
}

TEST(DownsampleCli, NonsenseFlagsFailWithoutOutput) {
  TempDir dir;
  const std::string in = makeRandomFile(dir), out = dir.path("out.vdb");
  for (const std::string flags : {"--factor 1", "--factor abc", "--factor 2.5", "--s-weight bogus", "--bogus",
                                  "--threads -2"}) {
    const auto r = runCommand(kDownsample + " " + flags + " " + quote(in) + " " + quote(out));
    EXPECT_NE(r.status, 0) << "flags '" << flags << "'";
    EXPECT_FALSE(r.err.empty()) << "flags '" << flags << "'";
    EXPECT_FALSE(exists(out)) << "flags '" << flags << "'";
  }
  EXPECT_NE(runCommand(kDownsample).status, 0) << "no arguments";
}

TEST(DownsampleCli, MissingInputIsOneErrorLineAndNoOutput) {
  TempDir dir;
  const std::string out = dir.path("out.vdb");
  const auto r = runCommand(kDownsample + " -f 2 " + quote(dir.path("absent.vdb")) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "vdb_sggx_downsample: error: " + dir.path("absent.vdb") + ": no such file\n");
  EXPECT_FALSE(exists(out));
}

// The output is checked before the input is even opened: here the input does not exist either.
TEST(DownsampleCli, UnwritableOutputFailsBeforeAnyWork) {
  TempDir dir;
  const std::string in = dir.path("absent.vdb"), out = dir.path("missing/out.vdb");
  auto r = runCommand(kDownsample + " -f 2 " + quote(in) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "vdb_sggx_downsample: error: " + out + ": no such folder '" + dir.path("missing") + "'\n");
  r = runCommand(kDownsample + " -f 2 " + quote(in) + " " + quote(dir.root().string()));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
  r = runCommand(kDownsample + " -f 2 --report " + quote(dir.path("missing/r.json")) + " " + quote(in) + " " +
                 quote(dir.path("out.vdb")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("r.json: no such folder"), std::string::npos) << r.err;
}

TEST(DownsampleCli, OutputsNeverOverwriteTheInputOrEachOther) {
  TempDir dir;
  const std::string in = makeRandomFile(dir);
  const std::string before = readFileBytes(in);
  auto r = runCommand(kDownsample + " -f 2 " + quote(in) + " " + quote(in));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("the output is the input"), std::string::npos) << r.err;
  r = runCommand("cd " + quote(dir.root().string()) + " && " + kDownsample + " -f 2 in.vdb ./in.vdb");
  EXPECT_EQ(r.status, 1) << "the same file by another name";
  r = runCommand(kDownsample + " -f 2 --report " + quote(in) + " " + quote(in) + " " + quote(dir.path("o.vdb")));
  EXPECT_EQ(r.status, 1);
  r = runCommand(kDownsample + " -f 2 --report - " + quote(in) + " - | cat > /dev/null");
  EXPECT_NE(r.err.find("both write to stdout"), std::string::npos) << r.err;
  EXPECT_EQ(readFileBytes(in), before);
  EXPECT_FALSE(exists(dir.path("o.vdb")));
}

TEST(DownsampleCli, DroppedGridsAreReportedOnStderrAndInTheReport) {
  TempDir dir;
  const MediumPtr medium = test::randomMedium(16);
  auto extra = test::namedGridLike(*medium, "temperature");
  openvdb::GridPtrVec grids = test::copyGrids(*medium);
  grids.push_back(extra);
  const std::string in = dir.path("in.vdb"), report = dir.path("r.json");
  test::writeRawVdb(in, grids);
  const auto r = runCommand(kDownsample + " -f 2 --report " + quote(report) + " " + quote(in) + " " +
                            quote(dir.path("out.vdb")));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err,
            "vdb_sggx_downsample: warning: dropped grid 'temperature': not part of the medium contract, so it was not "
            "downsampled\n");
  std::ifstream file(report);
  EXPECT_EQ(nlohmann::json::parse(file)["warnings"].size(), 1u);
}

TEST(DownsampleCli, BadMediaThroughStdinAreReportedAsStdin) {
  TempDir dir;
  const MediumPtr medium = test::randomMedium(16);
  openvdb::GridPtrVec grids = test::copyGrids(*medium);
  grids.push_back(medium->albedo->deepCopyGrid());  // a second 'albedo'
  test::writeRawVdb(dir.path("dup.vdb"), grids);
  auto r = runCommand(kDownsample + " -f 2 - " + quote(dir.path("out.vdb")) + " < " + quote(dir.path("dup.vdb")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("stdin: grid 'albedo': appears more than once"), std::string::npos) << r.err;

  for (auto it = medium->density->beginValueOn(); it; ++it) it.setValue(-1.0f);
  test::writeRawVdb(dir.path("negative.vdb"), test::copyGrids(*medium));
  r = runCommand("cat " + quote(dir.path("negative.vdb")) + " | " + kDownsample + " -f 2 - " + quote(dir.path("out.vdb")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("stdin: grid 'density': negative density -1"), std::string::npos) << r.err;
  EXPECT_FALSE(exists(dir.path("out.vdb")));
}

TEST(DownsampleCli, BadInputLeavesAnExistingOutputUntouched) {
  TempDir dir;
  const MediumPtr medium = test::randomMedium(16);
  for (auto it = medium->density->beginValueOn(); it; ++it) {
    if (*it > 0) {
      it.setValue(-1.0f);
      break;
    }
  }
  const std::string in = dir.path("negative.vdb"), out = dir.path("out.vdb");
  test::writeRawVdb(in, test::copyGrids(*medium));
  std::ofstream(out) << "previous result";
  const auto r = runCommand(kDownsample + " -f 2 " + quote(in) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(in + ": grid 'density': negative density -1"), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(readFileBytes(out), "previous result");
  EXPECT_EQ(test::listFiles(dir.root()), (std::vector<std::string>{"negative.vdb", "out.vdb"}));
}

TEST(DownsampleCli, EmptyStdinIsAnError) {
  TempDir dir;
  const auto r = runCommand("true | " + kDownsample + " -f 2 - " + quote(dir.path("out.vdb")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("stdin: not a readable VDB stream"), std::string::npos) << r.err;
  EXPECT_FALSE(exists(dir.path("out.vdb")));
}

// The acceptance test of the issue: two factor-2 steps through a pipe equal one factor-4 step.
TEST(DownsampleCli, PipedFactorTwoTwiceEqualsFactorFour) {
  TempDir dir;
  const std::string in = makeRandomFile(dir, 64);
  const std::string before = readFileBytes(in);
  const std::string chained = dir.path("chained.vdb"), direct = dir.path("direct.vdb");
  auto r = runCommand(kDownsample + " --factor 2 " + quote(in) + " - | " + kDownsample + " --factor 2 - " +
                      quote(chained));
  ASSERT_EQ(r.status, 0) << r.err;
  r = runCommand(kDownsample + " --factor 4 " + quote(in) + " " + quote(direct));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readFileBytes(in), before) << "inputs are never modified";

  const MediumPtr a = readMedium(chained), b = readMedium(direct);
  EXPECT_TRUE(test::gridsMatch(*b->density, *a->density, 1e-5));
  EXPECT_TRUE(test::gridsMatch(*b->albedo, *a->albedo, 1e-5));
  EXPECT_EQ(a->transform(), b->transform());
  const std::string history = a->metadata.metaValue<std::string>("history");
  EXPECT_NE(history.find("vdb_make_medium"), std::string::npos) << history;
  EXPECT_NE(history.find("vdb_sggx_downsample --factor 2 " + in + " -"), std::string::npos) << history;
  EXPECT_NE(history.find("vdb_sggx_downsample --factor 2 - " + chained), std::string::npos) << history;
}

// The two files' density, albedo and SGGX grids: the same active voxels and values, exactly.
void expectSameBaseGrids(const std::string& first, const std::string& second) {
  const MediumPtr a = readMedium(first), b = readMedium(second);
  EXPECT_TRUE(test::gridsMatch(*a->density, *b->density, 0));
  EXPECT_TRUE(test::gridsMatch(*a->albedo, *b->albedo, 0));
  EXPECT_TRUE(test::gridsMatch(*a->sggx_diag, *b->sggx_diag, 0));
  EXPECT_TRUE(test::gridsMatch(*a->sggx_offdiag, *b->sggx_offdiag, 0));
}

TEST(DownsampleCli, OutputDoesNotDependOnTheThreadCount) {
  TempDir dir;
  const std::string in = makeRandomFile(dir, 48);
  const std::string one = dir.path("one.vdb"), two = dir.path("two.vdb");
  ASSERT_EQ(runCommand(kDownsample + " -f 3 --s-weight density -j 1 " + quote(in) + " " + quote(one)).status, 0);
  ASSERT_EQ(runCommand(kDownsample + " -f 3 --s-weight density -j 2 " + quote(in) + " " + quote(two)).status, 0);
  expectSameBaseGrids(one, two);
}

// A file is read in slabs (docs/scaling.md §5): the same result as --in-core, in as many slabs as
// a small --memory asks for; a budget too small for one slab is one error line, nothing written.
TEST(DownsampleCli, SlabsGiveTheInCoreResultAndASmallBudgetIsRefused) {
  TempDir dir;
  const std::string in = makeRandomFile(dir, 64);
  const std::string slabs = dir.path("slabs.vdb"), whole = dir.path("whole.vdb"), none = dir.path("none.vdb");
  const auto r = runCommand(kDownsample + " -v -f 2 --memory 0.02 " + quote(in) + " " + quote(slabs));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("read in 4 pieces"), std::string::npos) << r.err;
  ASSERT_EQ(runCommand(kDownsample + " -f 2 --in-core " + quote(in) + " " + quote(whole)).status, 0);
  expectSameBaseGrids(whole, slabs);
  const auto small = runCommand(kDownsample + " -f 2 --memory 0.0001 " + quote(in) + " " + quote(none));
  EXPECT_EQ(small.status, 1);
  EXPECT_NE(small.err.find(in + ": a memory budget of 0.0001 GB is too small"), std::string::npos) << small.err;
  EXPECT_EQ(lineCount(small.err), 1) << small.err;
  EXPECT_FALSE(exists(none));
}

TEST(DownsampleCli, ReportAndVerboseSummaryCountVoxels) {
  TempDir dir;
  const std::string in = makeRandomFile(dir), out = dir.path("out.vdb"), report = dir.path("report.json");
  const auto r = runCommand(kDownsample + " -v -f 2 --report " + quote(report) + " " + quote(in) + " " + quote(out));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("active voxels"), std::string::npos) << r.err;
  std::ifstream file(report);
  const nlohmann::json json = nlohmann::json::parse(file);
  EXPECT_EQ(json["factor"], 2);
  EXPECT_EQ(json["s_weight"], "count");
  EXPECT_EQ(json["output"]["active_voxels"].get<std::uint64_t>(), readMedium(out)->density->activeVoxelCount());
  EXPECT_GT(json["input"]["file_bytes"].get<std::uint64_t>(), 0u);
  EXPECT_TRUE(json["seconds"].contains("downsample"));
}

TEST(MakeMediumCli, PipesIntoTheDownsampler) {
  TempDir dir;
  const std::string out = dir.path("out.vdb");
  const auto r = runCommand(kMakeMedium + " random --res 32 -o - | " + kDownsample + " -f 2 - " + quote(out));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_GT(readMedium(out)->density->activeVoxelCount(), 0u);
}

}  // namespace
}  // namespace vdbappear
