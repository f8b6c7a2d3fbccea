// vdb_info from the command line (issue 26): the grids a file holds and which the tools read, its box
// and value ranges against the medium read directly, foreign grids (Blender, Mantaflow, Houdini)
// named and marked as not read, a suggested render that shows a white smoke (against the white
// furnace as the negative control), and bad input.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/image_footprint.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace vdbappear {
namespace {

using nlohmann::json;
using test::kInfo;
using test::kMakeMedium;
using test::kRender;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

json infoJson(const std::string& path, const std::string& flags = "") {
  const auto r = runCommand(kInfo + " --json " + quote(path) + flags);
  EXPECT_EQ(r.status, 0) << r.err;
  return json::parse(r.out);
}

const json& gridNamed(const json& info, const std::string& name) {
  for (const json& g : info.at("grids"))
    if (g.at("name") == name) return g;
  throw std::runtime_error("no grid " + name);
}

TEST(InfoCli, HelpShowsUsageAndExamples) {
  const auto r = runCommand(kInfo + " --help");
  EXPECT_EQ(r.status, 0);
  for (const char* text : {"Usage:", "Examples:", "--json", "MEDIUM"}) EXPECT_NE(r.out.find(text), std::string::npos) << text;
}

// The figures are the medium's own: voxel count, voxel size, the box of the active cells, the
// density range and mean (tiles counted by their voxels), each albedo channel.
TEST(InfoCli, DescribesAMediumAsTheToolsReadIt) {
  const TempDir dir;
  const std::string path = dir.path("twill.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " twill --res 32 --yarns 4 -o " + quote(path)).status, 0);
  const json info = infoJson(path);
  const MediumPtr medium = readMedium(path);
  EXPECT_EQ(info.at("active_voxels").get<std::uint64_t>(), medium->density->activeVoxelCount());
  EXPECT_DOUBLE_EQ(info.at("voxel_size")[0].get<double>(), medium->transform().voxelSize()[0]);
  double lo = 1e30, hi = -1e30, sum = 0, count = 0, albedo_green_max = 0;
  for (auto v = medium->density->cbeginValueOn(); v; ++v) {
    lo = std::min(lo, double(*v));
    hi = std::max(hi, double(*v));
    sum += double(*v) * double(v.getVoxelCount());
    count += double(v.getVoxelCount());
  }
  for (auto v = medium->albedo->cbeginValueOn(); v; ++v) albedo_green_max = std::max(albedo_green_max, double((*v)[1]));
  EXPECT_DOUBLE_EQ(info.at("density").at("min").get<double>(), lo);
  EXPECT_DOUBLE_EQ(info.at("density").at("max").get<double>(), hi);
  EXPECT_NEAR(info.at("density").at("mean").get<double>(), sum / count, 1e-12 * hi);
  EXPECT_DOUBLE_EQ(info.at("albedo")[1].at("max").get<double>(), albedo_green_max);
  const openvdb::CoordBBox box = medium->density->evalActiveVoxelBoundingBox();
  const openvdb::Vec3d lower = medium->transform().indexToWorld(box.min().asVec3d() - openvdb::Vec3d(0.5));
  const openvdb::Vec3d upper = medium->transform().indexToWorld(box.max().asVec3d() + openvdb::Vec3d(0.5));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(info.at("world_box").at("min")[a].get<double>(), lower[a], 1e-9) << a;
    EXPECT_NEAR(info.at("world_box").at("max")[a].get<double>(), upper[a], 1e-9) << a;
  }
  for (const char* name : {"density", "albedo", "sggx_diag", "sggx_offdiag"}) EXPECT_TRUE(gridNamed(info, name).at("used").get<bool>()) << name;
  EXPECT_TRUE(info.at("metadata").contains("history"));
}

// A file as Mantaflow and Houdini write them: the contract's density, and grids no tool reads yet,
// each named with what it is and marked as not read, in the JSON and in the text. Read as it is
// (--from none); by default its Cd is detected as the albedo, which the notes say first.
TEST(InfoCli, NamesForeignGridsAndSaysTheyAreNotRead) {
  const TempDir dir;
  const MediumPtr cloud = test::randomMedium(8);
  openvdb::GridPtrVec grids{cloud->density->deepCopy()};
  for (const char* name : {"color_r", "temperature", "flame", "shadow", "mystery"}) {
    auto grid = test::namedGridLike(*cloud, name);
    grid->tree().setValueOn(openvdb::Coord(1, 2, 3), 0.5f);
    grids.push_back(grid);
  }
  for (const char* name : {"Cd", "vel"}) {
    auto grid = test::namedGridLike<openvdb::Vec3SGrid>(*cloud, name);
    grid->tree().setValueOn(openvdb::Coord(1, 2, 3), openvdb::Vec3s(0.5f));
    grids.push_back(grid);
  }
  const std::string path = dir.path("foreign.vdb");
  test::writeRawVdb(path, grids);
  const json detected = infoJson(path);
  EXPECT_TRUE(gridNamed(detected, "albedo").at("used").get<bool>());
  EXPECT_NE(detected.at("notes").at(0).get<std::string>().find("Houdini's Cd: read as --grid albedo=Cd"), std::string::npos)
      << detected.at("notes");
  const json info = infoJson(path, " --from none");
  EXPECT_TRUE(gridNamed(info, "density").at("used").get<bool>());
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"color_r", "Mantaflow"}, {"Cd", "Houdini"}, {"temperature", "emission"}, {"flame", "emission"},
      {"shadow", "shadow"}, {"vel", "velocities"}, {"mystery", "not part of the medium contract"}};
  for (const auto& [name, words] : expected) {
    const json& g = gridNamed(info, name);
    EXPECT_FALSE(g.at("used").get<bool>()) << name;
    EXPECT_NE(g.at("role").get<std::string>().find(words), std::string::npos) << name << ": " << g.at("role");
  }
  const std::string notes = info.at("notes").dump();
  EXPECT_NE(notes.find("no 'albedo' grid"), std::string::npos) << notes;
  EXPECT_NE(notes.find("'Cd'"), std::string::npos) << notes;
  const auto text = runCommand(kInfo + " " + quote(path) + " --from none");
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("NOT READ"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("vdb_render " + path), std::string::npos) << text.out;
}

// The suggested command, run as given (with this build's vdb_render, a small image and an EXR with
// alpha): the medium is framed (it covers part of the picture, not all of it), and a white smoke of
// albedo 1 shows under vdb_render's default lights (test::footprintOf). Control: the same smoke and
// camera under a white sky alone (the white furnace, --env 1): footprint and sky alike.
TEST(InfoCli, SuggestedRenderFramesAndShowsAWhiteSmoke) {
  const TempDir dir;
  const std::string cloud = dir.path("cloud.vdb"), smoke = dir.path("smoke.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cloud --res 32 -o " + quote(cloud)).status, 0);
  test::writeRawVdb(smoke, {readMedium(cloud)->density->deepCopy()});  // density alone, as a smoke cache: albedo 1
  const std::string suggested = infoJson(smoke).at("render_command").get<std::string>();
  ASSERT_EQ(suggested.rfind("vdb_render ", 0), 0u) << suggested;
  const std::size_t o = suggested.find(" -o "), after = suggested.find(' ', o + 4);
  ASSERT_NE(o, std::string::npos);
  EXPECT_EQ(suggested.find("--env"), std::string::npos) << "the default lights, not flags: " << suggested;
  // The suggested command with this build's vdb_render, writing `exr` with alpha, small; then `extra`.
  auto withOutput = [&](const std::string& exr, const std::string& extra) {
    return kRender + suggested.substr(10, o - 10) + " -o " + quote(exr) + suggested.substr(after) +
           " --res 64x48 --spp 32 --aov alpha" + extra;
  };
  const std::string lit = dir.path("lit.exr"), furnace = dir.path("furnace.exr");
  const std::string command = withOutput(lit, "");
  const auto r = runCommand(command);
  ASSERT_EQ(r.status, 0) << command << "\n" << r.err;
  const test::Footprint shown = test::footprintOf(lit);
  EXPECT_GT(shown.coverage, 0.05) << command;
  EXPECT_LT(shown.coverage, 0.8) << command;
  EXPECT_GT(shown.contrast, 0.5) << command;
  EXPECT_GT(shown.structure, 0.15) << command;
  ASSERT_EQ(runCommand(withOutput(furnace, " --env 1")).status, 0);
  const test::Footprint hidden = test::footprintOf(furnace);
  EXPECT_LT(hidden.contrast, 0.02) << "the white furnace hides a white smoke";
  EXPECT_LT(hidden.structure, 0.05) << "the white furnace hides a white smoke";
}

TEST(InfoCli, BadInputGivesOneErrorLine) {
  const TempDir dir;
  auto r = runCommand(kInfo + " " + quote(dir.path("missing.vdb")));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("missing.vdb"), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  const std::string cloud = dir.path("cloud.vdb"), truncated = dir.path("truncated.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cloud --res 16 -o " + quote(cloud)).status, 0);
  {
    std::ifstream in(cloud, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  r = runCommand(kInfo + " " + quote(truncated));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("truncated.vdb"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(runCommand(kInfo + " --json").status, 0);  // no file
  EXPECT_NE(runCommand(kInfo + " " + quote(cloud) + " --frobnicate").status, 0);
}

}  // namespace
}  // namespace vdbappear
