// vdb_optimize_weights from the command line: the written medium (weights = naive x factors, the
// metadata, base grids untouched), the log and report, the reference cache, determinism over
// threads, resumption equal to an uninterrupted run, and one clear error line with no output for
// each kind of bad input (missing or wrong media, damaged cache files and checkpoints, bad flags).
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kDownsample;
using test::kLobeCluster;
using test::kMakeMedium;
using test::kOptimize;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

// Tiny training runs: 16-pixel images, 4 samples per iteration.
const std::string kQuick = " --resolution 16 --spp 4 --reference-spp 8 --tolerance 0 ";

// A two-coloured twill and its 2-lobe, 2-cluster reduction at factor 4.
struct Media {
  TempDir dir;
  std::string full = dir.path("twill.vdb"), lobes = dir.path("lobes.vdb"), out = dir.path("out.vdb");
  Media() {
    EXPECT_EQ(runCommand(kMakeMedium + " twill --yarns 2 --res 32 -o " + quote(full)).status, 0);
    EXPECT_EQ(runCommand(kLobeCluster + " -f 4 --lobes 2 --clusters 2 " + quote(full) + " " + quote(lobes)).status, 0);
  }
  std::string args(const std::string& extra = "") const {
    return kOptimize + kQuick + extra + " " + quote(full) + " " + quote(lobes) + " " + quote(out);
  }
};

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

nlohmann::json factorsOf(const std::string& medium) {
  const MediumPtr m = readMedium(medium);
  return nlohmann::json::parse(m->metadata.metaValue<std::string>("weight_factors"))["factors"];
}

TEST(OptimizeWeightsCli, HelpHasExamples) {
  const auto help = runCommand(kOptimize + " --help");
  ASSERT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("Examples:"), std::string::npos);
  EXPECT_NE(help.out.find("--resume"), std::string::npos);
}

// OUT holds LOBES's base grids unchanged and lobe weights = naive weights x s_k w_kj of the voxel's
// cluster; the log has a line per iteration and the report the errors.
TEST(OptimizeWeightsCli, WritesTheOptimisedMediumLogAndReport) {
  const Media m;
  const std::string log = m.dir.path("run.jsonl"), report = m.dir.path("r.json");
  const auto r = runCommand(m.args("--iterations 3 --no-cache --log " + quote(log) + " --report " + quote(report)));
  ASSERT_EQ(r.status, 0) << r.err;
  const MediumPtr lobes = readMedium(m.lobes), out = readMedium(m.out);
  const nlohmann::json record = nlohmann::json::parse(out->metadata.metaValue<std::string>("weight_factors"));
  EXPECT_EQ(record["iterations"], 3);
  EXPECT_EQ(record["factors"]["mode"], "colour-scales");  // the twill's weights are coloured
  EXPECT_TRUE(test::gridsMatch(*lobes->density, *out->density, 0.0));
  EXPECT_TRUE(test::gridsMatch(*lobes->albedo, *out->albedo, 0.0));
  auto cluster = findOtherGrid<openvdb::Int32Grid>(*out, grid_names::kCluster)->getConstAccessor();
  int checked = 0;
  for (int j = 0; j < 2; ++j) {
    const std::string name = "lobe" + std::to_string(j) + "_weight";
    auto before = findOtherGrid<openvdb::Vec3SGrid>(*lobes, name)->getConstAccessor();
    for (auto v = findOtherGrid<openvdb::Vec3SGrid>(*out, name)->cbeginValueOn(); v; ++v, ++checked) {
      const int k = cluster.getValue(v.getCoord());
      const nlohmann::json& f = record["factors"];
      for (int c = 0; c < 3; ++c) {
        const double scale = f["s"][k][c].get<double>() * f["w"][k][j][c].get<double>();
        EXPECT_NEAR((*v)[c], before.getValue(v.getCoord())[c] * scale, 1e-6) << name << " at " << v.getCoord();
      }
    }
  }
  EXPECT_GT(checked, 0);
  std::ifstream in(log);
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) {
    const auto entry = nlohmann::json::parse(line);
    EXPECT_EQ(entry["t"], ++lines);
    for (const char* key : {"E", "factors", "gradient", "step", "seconds"}) EXPECT_TRUE(entry.contains(key)) << key;
  }
  EXPECT_EQ(lines, 3);
  const nlohmann::json rep = readJson(report);
  EXPECT_TRUE(rep.contains("E_naive"));
  EXPECT_TRUE(rep.contains("E_final"));
  EXPECT_EQ(rep["cache_hits"], 0);
}

TEST(OptimizeWeightsCli, SecondRunFindsTheReferencesInTheCache) {
  const Media m;
  const std::string cache = m.dir.path("cache"), report = m.dir.path("r.json");
  ASSERT_EQ(runCommand(m.args("--iterations 1 --cache " + quote(cache) + " --report " + quote(report))).status, 0);
  EXPECT_EQ(readJson(report)["cache_hits"], 0);
  const auto r = runCommand(m.args("--iterations 1 -v --cache " + quote(cache) + " --report " + quote(report)));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readJson(report)["cache_hits"], readJson(report)["references"]);
  EXPECT_NE(r.err.find("references: 20 of 20 from the cache"), std::string::npos) << r.err;
  // FULL's float grids (--full-precision) render other references than its compact form: not found.
  ASSERT_EQ(runCommand(m.args("--iterations 1 --full-precision --cache " + quote(cache) + " --report " + quote(report))).status, 0);
  EXPECT_EQ(readJson(report)["cache_hits"], 0) << "the float grids found the compact form's references";
}

// --grid maps FULL's foreign grids, and the mapping is part of FULL's key in the cache: an albedo
// read at 0.9 of its value is another medium, whose references are rendered anew and then found.
// (A mapped density would fail the check that LOBES was downsampled from FULL: Eq. 6 keeps mass.)
// A mapping that names a missing grid is one error line naming it, and no output.
TEST(OptimizeWeightsCli, GridMappingReadsFullAndAddressesItsReferences) {
  const Media m;
  const std::string cache = m.dir.path("cache"), report = m.dir.path("r.json");
  const std::string darker = " --grid albedo=albedo:0.9 --cache " + quote(cache) + " --report " + quote(report);
  ASSERT_EQ(runCommand(m.args("--iterations 1 --cache " + quote(cache) + " --report " + quote(report))).status, 0);
  auto r = runCommand(m.args("--iterations 1" + darker));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readJson(report)["cache_hits"], 0) << "a mapped FULL found the unmapped one's references";
  r = runCommand(m.args("--iterations 1" + darker));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readJson(report)["cache_hits"], readJson(report)["references"]);

  std::filesystem::remove(m.out);
  r = runCommand(m.args("--iterations 1 --no-cache --grid albedo=Cd"));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("Cd"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(m.full), std::string::npos) << r.err;
  EXPECT_FALSE(exists(m.out));
}

TEST(OptimizeWeightsCli, SameFactorsWithOneThreadOrAllAndOtherSeedsDiffer) {
  const Media m;
  const std::string a = m.dir.path("a.vdb"), b = m.dir.path("b.vdb"), c = m.dir.path("c.vdb");
  const std::string common = kOptimize + kQuick + " --iterations 2 --no-cache " + quote(m.full) + " " + quote(m.lobes) + " ";
  ASSERT_EQ(runCommand(common + quote(a) + " -j 1 --seed 3").status, 0);
  ASSERT_EQ(runCommand(common + quote(b) + " --seed 3").status, 0);
  ASSERT_EQ(runCommand(common + quote(c) + " --seed 4").status, 0);
  EXPECT_EQ(factorsOf(a), factorsOf(b));
  EXPECT_NE(factorsOf(a), factorsOf(c));
}

TEST(OptimizeWeightsCli, ResumingGivesTheUninterruptedRun) {
  const Media m;
  const std::string whole = m.dir.path("whole.vdb"), part = m.dir.path("part.vdb"), ckpt = m.dir.path("run.ckpt");
  const std::string common = kOptimize + kQuick + " --no-cache " + quote(m.full) + " " + quote(m.lobes) + " ";
  ASSERT_EQ(runCommand(common + quote(whole) + " --iterations 3").status, 0);
  ASSERT_EQ(runCommand(common + quote(part) + " --iterations 2 --checkpoint " + quote(ckpt)).status, 0);
  const auto r = runCommand(common + quote(part) + " --iterations 3 --resume " + quote(ckpt));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("resumed from"), std::string::npos);
  EXPECT_EQ(factorsOf(whole), factorsOf(part));
}

// Each case: exit status 1, one line "vdb_optimize_weights: error: ..." naming the culprit, no OUT.
void expectRefused(const Media& m, const std::string& command, const std::string& names) {
  const auto r = runCommand(command);
  EXPECT_EQ(r.status, 1) << command << "\n" << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("vdb_optimize_weights: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(names), std::string::npos) << "expected '" << names << "' in: " << r.err;
  EXPECT_FALSE(exists(m.out)) << command;
}

TEST(OptimizeWeightsCli, BadMediaAreOneErrorLineAndNoOutput) {
  const Media m;
  const std::string tail = " " + quote(m.out);
  const std::string absent = m.dir.path("absent.vdb");
  expectRefused(m, kOptimize + " " + quote(absent) + " " + quote(m.lobes) + tail, absent + ": no such file");
  expectRefused(m, kOptimize + " - " + quote(m.lobes) + tail, "FULL must be a file");

  // LOBES without lobe grids (a naive reduction).
  const std::string naive = m.dir.path("naive.vdb");
  ASSERT_EQ(runCommand(kDownsample + " -f 4 " + quote(m.full) + " " + quote(naive)).status, 0);
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(naive) + tail, naive + ": no grid 'lobe0_weight'");

  // LOBES of another medium with the same voxels: not downsampled from FULL.
  const std::string other = m.dir.path("other.vdb"), other_lobes = m.dir.path("other_lobes.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " twill --yarns 2 --res 32 --seed 9 --fiber-density 20 -o " + quote(other)).status, 0);
  ASSERT_EQ(runCommand(kLobeCluster + " -f 4 --clusters 2 " + quote(other) + " " + quote(other_lobes)).status, 0);
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(other_lobes) + tail, "not downsampled from " + m.full);

  // Mismatched transforms: LOBES reduced by 2 from a cube.
  const std::string cube = m.dir.path("cube.vdb"), cube_lobes = m.dir.path("cube_lobes.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cube --res 16 --phase sggx-fiber -o " + quote(cube)).status, 0);
  ASSERT_EQ(runCommand(kLobeCluster + " -f 2 " + quote(cube) + " " + quote(cube_lobes)).status, 0);
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(cube_lobes) + tail, "is not " + m.full + "'s coarsened");

  // An optimised medium given again as LOBES.
  const std::string optimised = m.dir.path("optimised.vdb");
  ASSERT_EQ(runCommand(kOptimize + kQuick + " --iterations 1 --no-cache " + quote(m.full) + " " + quote(m.lobes) + " " +
                       quote(optimised)).status, 0);
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(optimised) + tail, "already holds optimised lobe weights");

  // A truncated LOBES file.
  const std::string truncated = m.dir.path("truncated.vdb");
  {
    const std::string bytes = test::readFileBytes(m.lobes);
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(truncated) + tail, truncated);
}

TEST(OptimizeWeightsCli, DamagedCacheFilesAndCheckpointsAreRefused) {
  const Media m;
  const std::string cache = m.dir.path("cache"), ckpt = m.dir.path("run.ckpt");
  ASSERT_EQ(runCommand(m.args("--iterations 1 --cache " + quote(cache) + " --checkpoint " + quote(ckpt))).status, 0);
  std::filesystem::remove(m.out);
  std::vector<std::string> refs;
  for (const auto& entry : std::filesystem::directory_iterator(cache)) refs.push_back(entry.path().string());
  ASSERT_EQ(refs.size(), 20u);
  std::sort(refs.begin(), refs.end());
  const std::string bytes = test::readFileBytes(refs[0]);
  std::ofstream(refs[0], std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() - 100);
  expectRefused(m, m.args("--cache " + quote(cache)), refs[0] + ": truncated");
  std::string other_version = bytes;
  other_version.replace(other_version.find(" 2 ") + 3, 0, "9");  // format 2, version 0.1.0 -> 90.1.0
  std::ofstream(refs[0], std::ios::binary | std::ios::trunc) << other_version;
  expectRefused(m, m.args("--cache " + quote(cache)), refs[0] + ": written by vdbappear 9");

  // A checkpoint of other settings (another seed), and a truncated one.
  expectRefused(m, m.args("--no-cache --seed 5 --resume " + quote(ckpt)), ckpt + ": made with other inputs");
  const std::string text = test::readFileBytes(ckpt);
  std::ofstream(ckpt, std::ios::trunc) << text.substr(0, text.size() / 2);
  expectRefused(m, m.args("--no-cache --resume " + quote(ckpt)), ckpt + ": not a complete checkpoint");
}

TEST(OptimizeWeightsCli, NonsenseFlagsFailWithoutOutput) {
  const Media m;
  for (const std::string flags : {"--spp 1", "--training-lights sh7", "--training-lights ground", "--training-views +w",
                                  "--colour pink", "--per-channel --colour grey", "--iterations 0", "--steps fast",
                                  "--resolution 3", "--interp cubic"}) {
    const auto r = runCommand(m.args(flags + " --no-cache"));
    EXPECT_NE(r.status, 0) << flags;
    EXPECT_FALSE(r.err.empty()) << flags;
    EXPECT_FALSE(exists(m.out)) << flags;
  }
  expectRefused(m, kOptimize + " " + quote(m.full) + " " + quote(m.lobes) + " " + quote(m.lobes), "the output is the input");
}

}  // namespace
}  // namespace vdbappear
