// vdb_lobe_cluster from the command line: flags, errors, the report, pipes, and the written medium
// as vdb_sggx_downsample and vdb_render see it.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/identical_media.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kDownsample;
using test::kLobeCluster;
using test::kMakeMedium;
using test::kRender;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

// A small two-coloured twill made by vdb_make_medium.
std::string makeTwill(const TempDir& dir) {
  const std::string path = dir.path("twill.vdb");
  const auto r = runCommand(kMakeMedium + " twill --yarns 2 --res 64 -o " + quote(path));
  EXPECT_EQ(r.status, 0) << r.err;
  return path;
}

TEST(LobeClusterCli, HelpShowsUsageAndExamples) {
  const auto r = runCommand(kLobeCluster + " --help");
  EXPECT_EQ(r.status, 0);
  for (const char* text : {"Usage:", "Examples:", "--max-lobes", "--lobes", "--clusters", "--jitter", "--seed"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
}

TEST(LobeClusterCli, NonsenseFlagsFailWithoutOutput) {
  TempDir dir;
  const std::string in = makeTwill(dir), out = dir.path("out.vdb");
  for (const std::string flags : {"--factor 1", "--lobes 0", "--lobes 6", "--max-lobes 0", "--lobes 2 --max-lobes 3",
                                  "--lobes 2 --keep-ratio 0.3", "--keep-ratio 2", "--clusters 0", "--jitter -0.1",
                                  "--seed -1", "--bogus"}) {
    const auto r = runCommand(kLobeCluster + " " + flags + " " + quote(in) + " " + quote(out));
    EXPECT_NE(r.status, 0) << "flags '" << flags << "'";
    EXPECT_FALSE(r.err.empty()) << "flags '" << flags << "'";
    EXPECT_FALSE(exists(out)) << "flags '" << flags << "'";
  }
}

TEST(LobeClusterCli, BadInputsAreOneErrorLineAndNoOutput) {
  TempDir dir;
  const std::string out = dir.path("out.vdb");
  auto r = runCommand(kLobeCluster + " -f 2 " + quote(dir.path("absent.vdb")) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "vdb_lobe_cluster: error: " + dir.path("absent.vdb") + ": no such file\n");
  EXPECT_FALSE(exists(out));

  // A medium that already has lobe grids cannot be clustered again.
  const std::string lobes = dir.path("lobes.vdb");
  ASSERT_EQ(runCommand(kLobeCluster + " -f 2 " + quote(makeTwill(dir)) + " " + quote(lobes)).status, 0);
  r = runCommand(kLobeCluster + " -f 2 " + quote(lobes) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(lobes + ": grid '"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("': the medium is already multi-lobe"), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_FALSE(exists(out));

  // A medium without SGGX grids (here HG) has no lobes to fit.
  const std::string hg = dir.path("hg.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cube --res 16 --phase hg --g 0.5 -o " + quote(hg)).status, 0);
  r = runCommand(kLobeCluster + " -f 2 " + quote(hg) + " " + quote(out));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(hg + ": no 'sggx_diag' or 'sggx_offdiag' grid"), std::string::npos) << r.err;
  EXPECT_FALSE(exists(out));
}

// The base grids are exactly vdb_sggx_downsample's with --s-weight count; the lobe grids and
// metadata are present, and the report tells the same story as the file.
TEST(LobeClusterCli, BaseGridsAreTheNaiveResultAndTheReportMatchesTheFile) {
  TempDir dir;
  const std::string in = makeTwill(dir), naive = dir.path("naive.vdb"), out = dir.path("lobes.vdb"),
                    report = dir.path("r.json");
  ASSERT_EQ(runCommand(kDownsample + " -f 4 --s-weight count " + quote(in) + " " + quote(naive)).status, 0);
  const auto r = runCommand(kLobeCluster + " -f 4 --clusters 2 --seed 3 --report " + quote(report) + " " + quote(in) +
                            " " + quote(out));
  ASSERT_EQ(r.status, 0) << r.err;
  const MediumPtr expected = readMedium(naive), actual = readMedium(out);
  EXPECT_TRUE(test::gridsMatch(*expected->density, *actual->density, 0));
  EXPECT_TRUE(test::gridsMatch(*expected->albedo, *actual->albedo, 0));
  EXPECT_TRUE(test::gridsMatch(*expected->sggx_diag, *actual->sggx_diag, 0));
  EXPECT_TRUE(test::gridsMatch(*expected->sggx_offdiag, *actual->sggx_offdiag, 0));

  std::ifstream file(report);
  const auto json = nlohmann::json::parse(file);
  const int m = json["lobe_count"];
  EXPECT_GE(m, 1);
  EXPECT_LE(m, 3);
  EXPECT_EQ(actual->metadata.metaValue<int>("lobe_count"), m);
  EXPECT_EQ(actual->metadata.metaValue<int>("cluster_count"), 2);
  EXPECT_EQ(json["clusters"].size(), 2u);
  EXPECT_EQ(json["voxels"].get<std::uint64_t>(), actual->density->activeVoxelCount());
  std::uint64_t fitted = 0;
  for (const auto& row : json["error_by_lobes"]) {
    fitted += row["voxels_fitted_with"].get<std::uint64_t>();
    EXPECT_GE(row["relative_l2_error"].get<double>(), 0);
  }
  EXPECT_EQ(fitted, json["voxels"].get<std::uint64_t>());
  EXPECT_GT(json["voxels_per_second"].get<double>(), 0);
  std::vector<std::string> names;
  for (const auto& grid : actual->other_grids) names.push_back(grid->getName());
  for (int j = 0; j < m; ++j)
    for (const char* what : {"diag", "offdiag", "fraction", "weight"})
      EXPECT_NE(std::find(names.begin(), names.end(), "lobe" + std::to_string(j) + "_" + what), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "cluster"), names.end());
}

// One lobe per voxel is the naive medium in lobe form (W = albedo, S = naive S): vdb_render, which
// reads the lobe grids, renders the same picture from both files (up to float rounding of S).
TEST(LobeClusterCli, OneLobeRendersLikeTheNaiveMediumThroughPipes) {
  TempDir dir;
  const std::string naive = dir.path("naive.exr"), lobes = dir.path("lobes.exr");
  const std::string make = kMakeMedium + " twill --yarns 2 --res 48 -o - | ";
  // Both media in their float grids: the naive one would otherwise be rendered in the compact form
  // (half-float S), which the lobe grids do not take.
  const std::string render = " - --full-precision --res 24 --spp 8 --seed 2 --view +z --sun 0.3,0.2,-1,3 --env 0.2 -o ";
  auto r = runCommand(make + kDownsample + " -f 4 - - | " + kRender + render + quote(naive));
  ASSERT_EQ(r.status, 0) << r.err;
  r = runCommand(make + kLobeCluster + " -f 4 --lobes 1 - - | " + kRender + render + quote(lobes));
  ASSERT_EQ(r.status, 0) << r.err;
  const ImageChannels a = readImageChannels(naive), b = readImageChannels(lobes);
  ASSERT_EQ(a.values.size(), b.values.size());
  double sum = 0, difference = 0;
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    sum += a.values[i];
    difference += std::abs(double(a.values[i]) - b.values[i]);
  }
  EXPECT_GT(sum, 0);
  EXPECT_LT(difference, 1e-4 * sum);
}

// A file is read in slabs (docs/scaling.md §5): the same medium and report as --in-core, in as
// many slabs as a small --memory asks for; a budget too small for one slab is one error line,
// nothing written.
TEST(LobeClusterCli, SlabsGiveTheInCoreResultAndASmallBudgetIsRefused) {
  TempDir dir;
  const std::string in = dir.path("twill.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " twill --yarns 2 --res 96 -o " + quote(in)).status, 0);
  const std::string slabs = dir.path("slabs.vdb"), whole = dir.path("whole.vdb"), none = dir.path("none.vdb");
  const std::string flags = " -f 2 --max-lobes 3 --clusters 3 --jitter 0.01 ";
  const auto r = runCommand(kLobeCluster + flags + "-v --memory 0.03 --report " + quote(dir.path("slabs.json")) + " " +
                            quote(in) + " " + quote(slabs));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("read in 2 pieces"), std::string::npos) << r.err;
  ASSERT_EQ(runCommand(kLobeCluster + flags + "--in-core --report " + quote(dir.path("whole.json")) + " " + quote(in) +
                       " " + quote(whole))
                .status,
            0);
  const MediumPtr whole_medium = readMedium(whole), slab_medium = readMedium(slabs);
  for (Medium* medium : {whole_medium.get(), slab_medium.get()}) medium->metadata.removeMeta("history");  // the commands differ
  EXPECT_TRUE(test::identicalMedia(*whole_medium, *slab_medium));
  nlohmann::json reports[2];
  for (int i = 0; i < 2; ++i) {
    std::ifstream file(dir.path(i == 0 ? "whole.json" : "slabs.json"));
    const nlohmann::json report = nlohmann::json::parse(file);
    for (const char* key : {"clusters", "error_by_lobes", "lobe_count", "rule_on_whole_medium", "voxels",
                            "voxels_exact_with_one_lobe", "warnings"})
      reports[i][key] = report[key];
    for (const char* side : {"input", "output"})
      for (const auto& grid : report[side]["grids"]) reports[i][side][grid["name"].get<std::string>()] = grid["active_voxels"];
  }
  EXPECT_EQ(reports[0], reports[1]) << "clusters, references, fit errors and voxel counts as the whole read's";

  const auto small = runCommand(kLobeCluster + flags + "--memory 0.0001 " + quote(in) + " " + quote(none));
  EXPECT_EQ(small.status, 1);
  EXPECT_NE(small.err.find(in + ": a memory budget of 0.0001 GB is too small"), std::string::npos) << small.err;
  EXPECT_EQ(lineCount(small.err), 1) << small.err;
  EXPECT_FALSE(exists(none));
}

}  // namespace
}  // namespace vdbappear
