// Every tool on the foreign files kept in grids/blender/ (Mantaflow caches baked by Debian's Blender
// 3.4, scripts/make_blender_grids.sh) and grids/houdini/ (the fire under Houdini's grid names, with a
// `Cd`, scripts/make_houdini_grids.py): it succeeds, or refuses with its documented one-line error
// and writes nothing (issue 26). The fire glows by Blender's preset (docs/medium.md §12); the smoke,
// whose heat Quick Smoke's smoke material does not light, does not; nor does the Houdini file, whose
// fire the Houdini preset does not read.
#include "libvdbappear/image/image_file.h"

#include "cli/run_command.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>

namespace vdbappear {
namespace {

using test::quote;
using test::runCommand;
using test::TempDir;

// "blender/smoke24": grids/blender/smoke24.vdb
std::string foreignFile(const std::string& name) { return std::string(FOREIGN_GRIDS_DIR) + "/" + name + ".vdb"; }

int errorLines(const std::string& err) {
  int n = 0;
  for (std::size_t at = err.find("error:"); at != std::string::npos; at = err.find("error:", at + 1)) ++n;
  return n;
}

struct Expected {
  std::string command;  // after the file: the rest of the command line, OUT for the output path
  std::string refusal;  // empty: succeeds and writes OUT
};

std::string withOutput(std::string command, const std::string& out) {
  const std::size_t at = command.find("OUT");
  return at == std::string::npos ? command : command.replace(at, 3, quote(out));
}

TEST(ForeignFiles, EveryToolReadsOrRefusesThem) {
  const std::vector<std::pair<std::string, Expected>> tools = {
      {VDB_INFO, {"", ""}},
      {VDB_INFO, {"--json", ""}},
      {VDB_RENDER, {"-o OUT --res 24x24 --spp 4", ""}},
      {VDB_PREVIEW, {"-o OUT --width 32", ""}},
      {VDB_SGGX_DOWNSAMPLE, {"-f 2 OUT", ""}},
      {VDB_SIMILARITY, {"OUT", ""}},
      {VDB_LOBE_CLUSTER, {"-f 2 OUT", "no 'sggx_diag' or 'sggx_offdiag' grid: every voxel has the same (isotropic) flakes"}},
      {VDB_OPTIMIZE_WEIGHTS, {"FILE OUT", "no grid 'lobe0_weight': not a multi-lobe medium"}}};
  for (const std::string name : {"blender/smoke24", "blender/fire24", "houdini/pyro24"}) {
    const std::string file = foreignFile(name);
    ASSERT_TRUE(std::filesystem::exists(file)) << file;
    for (const auto& [tool, expected] : tools) {
      const TempDir dir;
      const std::string out = dir.path(expected.command.find("-o OUT") != std::string::npos ? "out.png" : "out.vdb");
      std::string rest = withOutput(expected.command, out);
      if (const std::size_t at = rest.find("FILE"); at != std::string::npos) rest.replace(at, 4, quote(file));
      const auto r = runCommand(quote(tool) + " " + quote(file) + " " + rest);
      const std::string what = name + ": " + std::filesystem::path(tool).filename().string() + " " + expected.command;
      if (expected.refusal.empty()) {
        EXPECT_EQ(r.status, 0) << what << "\n" << r.err;
        if (expected.command.find("OUT") != std::string::npos) EXPECT_TRUE(std::filesystem::exists(out)) << what;
        if (expected.command == "--json") EXPECT_NO_THROW(nlohmann::json::parse(r.out)) << what;
      } else {
        EXPECT_EQ(r.status, 1) << what;
        EXPECT_EQ(errorLines(r.err), 1) << what << "\n" << r.err;
        EXPECT_NE(r.err.find(file + ": " + expected.refusal), std::string::npos) << what << "\n" << r.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << what;
      }
    }
  }
}

double meanOf(const std::string& image_path) {
  const ImageChannels image = readImageChannels(image_path);
  double sum = 0;
  for (int i = 0; i < image.width * image.height; ++i)
    for (int c = 0; c < 3; ++c) sum += image.values[std::size_t(i) * image.names.size() + std::size_t(c)];
  return sum / (3.0 * image.width * image.height);
}

// With no light (--env 0) the fire shows its own light, and the smoke is black; --from none reads
// the fire's grids as they are, without light. vdb_info gives the fire's emission and its convention.
TEST(ForeignFiles, TheFireGlowsAndTheSmokeDoesNot) {
  const TempDir dir;
  const auto render = [&](const std::string& name, const std::string& flags) {
    const std::string out = dir.path(std::filesystem::path(name).filename().string() + ".exr");
    const auto r = runCommand(quote(VDB_RENDER) + " " + quote(foreignFile(name)) + " -o " + quote(out) +
                              " --res 24x24 --spp 16 --env 0 --camera-pos 5.8,-5.1,5.2 --camera-target 1.2,1.2,2.1 " + flags);
    EXPECT_EQ(r.status, 0) << r.err;
    return meanOf(out);
  };
  EXPECT_GT(render("blender/fire24", ""), 0.01);
  EXPECT_EQ(render("blender/fire24", "--from none"), 0.0);
  EXPECT_EQ(render("blender/smoke24", ""), 0.0);
  EXPECT_EQ(render("houdini/pyro24", ""), 0.0);
  const auto info = runCommand(quote(VDB_INFO) + " " + quote(foreignFile("blender/fire24")) + " --json");
  ASSERT_EQ(info.status, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["emission"]["convention"], "cycles");
  EXPECT_GT(json["emission"]["channels"][0]["max"].get<double>(), 1.0);  // about 3000 K at the hottest
  EXPECT_EQ(json["emission"]["blackbody"]["intensity"], 1.0);
  EXPECT_NEAR(json["emission"]["blackbody"]["kelvin"]["max"].get<double>(), 2900, 100);  // temperature 0 to 2.9
  EXPECT_TRUE(nlohmann::json::parse(runCommand(quote(VDB_INFO) + " " + quote(foreignFile("blender/smoke24")) + " --json").out)["emission"].is_null());
}

// The Houdini-convention file: its `Cd` is read as the albedo (detected, with a note), its fire
// grids are left unread with a note, and the render shows the colour (a warm smoke under the default
// lights: red above blue). Negative control: --from none reads no colour, and the smoke is grey.
TEST(ForeignFiles, AHoudiniFilesCdIsItsAlbedo) {
  const std::string file = foreignFile("houdini/pyro24");
  const auto info = runCommand(quote(VDB_INFO) + " " + quote(file) + " --json");
  ASSERT_EQ(info.status, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_FALSE(json["albedo"].is_null());
  EXPECT_NEAR(json["albedo"][0]["max"].get<double>(), 0.95, 1e-6);
  EXPECT_TRUE(json["emission"].is_null());
  const std::string notes = json["notes"].dump();
  EXPECT_NE(notes.find("read as --grid albedo=Cd"), std::string::npos) << notes;
  EXPECT_NE(notes.find("temperature"), std::string::npos) << notes;
  const TempDir dir;
  const auto channelMeans = [&](const std::string& flags) {
    const std::string out = dir.path("pyro.exr");
    const auto r = runCommand(quote(VDB_RENDER) + " " + quote(file) + " -o " + quote(out) + " --res 24x24 --spp 16 " + flags);
    EXPECT_EQ(r.status, 0) << r.err;
    const ImageChannels image = readImageChannels(out);
    std::array<double, 3> sums{};
    for (int i = 0; i < image.width * image.height; ++i)
      for (int c = 0; c < 3; ++c) sums[std::size_t(c)] += image.values[std::size_t(i) * image.names.size() + std::size_t(c)];
    return sums;
  };
  const auto warm = channelMeans(""), grey = channelMeans("--from none");
  EXPECT_GT(warm[0], 1.1 * warm[2]) << "Cd's red above its blue";
  EXPECT_NEAR(grey[0] / grey[2], 1.0, 0.05) << "no colour read: a grey smoke under white lights";
}

}  // namespace
}  // namespace vdbappear
