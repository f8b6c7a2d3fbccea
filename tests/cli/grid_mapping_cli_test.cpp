// --grid ROLE=GRID (io/grid_mapping.h, docs/medium.md §12) from the command line: every tool that
// reads media takes it; a Houdini-style `Cd` colours a render and reaches a downsampled file, and so
// does Mantaflow's colour times density divided by the density; a
// mapping that names a missing grid or a malformed rule fails with one line and writes nothing.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <openvdb/tools/ValueTransformer.h>

#include <algorithm>
#include <filesystem>

namespace vdbappear {
namespace {

using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

// The golden cube with a red `Cd` on its density's voxels, as Houdini would name the colour.
std::string cubeWithCd(const TempDir& dir) {
  const MediumPtr cube = readMedium(std::string(GOLDEN_DIR) + "/cube8.vdb");
  auto cd = test::namedGridLike<openvdb::Vec3SGrid>(*cube, "Cd");
  cd->tree().topologyUnion(cube->density->tree());
  openvdb::tools::foreach(cd->beginValueOn(), [](const openvdb::Vec3SGrid::ValueOnIter& it) {
    it.setValue(openvdb::Vec3s(0.9f, 0.2f, 0.2f));
  });
  const std::string path = dir.path("cube_cd.vdb");
  test::writeRawVdb(path, {cube->density->deepCopy(), cd});
  return path;
}

// The same cube as Mantaflow writes colour: color_r, _g, _b = density x (0.9, 0.2, 0.2).
std::string cubeWithMantaflowColour(const TempDir& dir) {
  const MediumPtr cube = readMedium(std::string(GOLDEN_DIR) + "/cube8.vdb");
  openvdb::GridPtrVec grids = {cube->density->deepCopy()};
  const float colour[3] = {0.9f, 0.2f, 0.2f};
  const char* names[3] = {"color_r", "color_g", "color_b"};
  for (int c = 0; c < 3; ++c) {
    auto channel = cube->density->deepCopy();
    channel->setName(names[c]);
    const float k = colour[c];
    openvdb::tools::foreach(channel->beginValueOn(), [k](const openvdb::FloatGrid::ValueOnIter& it) {
      it.setValue(it.getValue() * k);
    });
    grids.push_back(channel);
  }
  const std::string path = dir.path("cube_mantaflow.vdb");
  test::writeRawVdb(path, grids);
  return path;
}

double meanChannel(const RgbImage& image, int c) {
  double sum = 0;
  for (std::size_t i = c; i < image.pixels.size(); i += 3) sum += image.pixels[i];
  return sum / (image.pixels.size() / 3);
}

TEST(GridMappingCli, EveryToolThatReadsMediaTakesGrid) {
  for (const char* tool : {VDB_INFO, VDB_PREVIEW, VDB_RENDER, VDB_SGGX_DOWNSAMPLE, VDB_LOBE_CLUSTER, VDB_SIMILARITY,
                           VDB_EXEMPLAR_STACK}) {
    const auto help = runCommand(quote(tool) + " --help");
    EXPECT_NE(help.out.find("--grid ROLE=GRID"), std::string::npos) << tool;
    EXPECT_NE(help.out.find("--from auto|blender|houdini|none"), std::string::npos) << tool;
  }
}

// A red Cd read as the albedo makes a red cube; with --from none and no rule the cube is white
// (control).
TEST(GridMappingCli, RenderSeesTheMappedColour) {
  const TempDir dir;
  const std::string input = cubeWithCd(dir), red = dir.path("red.exr"), white = dir.path("white.exr");
  const std::string flags = " --res 16 --spp 8 --env 1 --view -x";
  ASSERT_EQ(runCommand(quote(VDB_RENDER) + " " + quote(input) + " --grid albedo=Cd -o " + quote(red) + flags).status, 0);
  ASSERT_EQ(runCommand(quote(VDB_RENDER) + " " + quote(input) + " --from none -o " + quote(white) + flags).status, 0);
  const RgbImage r = readRgbImage(red), w = readRgbImage(white);
  EXPECT_GT(meanChannel(r, 0), 1.3 * meanChannel(r, 1));
  EXPECT_NEAR(meanChannel(w, 0), meanChannel(w, 1), 1e-6);
}

// Mantaflow's colour times density, divided back by the density, renders as the colour itself: the
// red cube of a Cd of (0.9, 0.2, 0.2). Undivided, the channels (density 5 to 15 times the colour)
// are no albedo, and the render is refused (control).
TEST(GridMappingCli, MantaflowColourOverDensityRendersTheColour) {
  const TempDir dir;
  const std::string mantaflow = cubeWithMantaflowColour(dir), houdini = cubeWithCd(dir);
  const std::string divided = dir.path("divided.exr"), cd = dir.path("cd.exr"), refused = dir.path("refused.exr");
  const std::string flags = " --res 16 --spp 8 --env 1 --view -x";
  ASSERT_EQ(runCommand(quote(VDB_RENDER) + " " + quote(mantaflow) +
                       " --grid albedo=color_r,color_g,color_b/density -o " + quote(divided) + flags)
                .status,
            0);
  ASSERT_EQ(runCommand(quote(VDB_RENDER) + " " + quote(houdini) + " --grid albedo=Cd -o " + quote(cd) + flags).status, 0);
  const RgbImage a = readRgbImage(divided), b = readRgbImage(cd);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(meanChannel(a, c), meanChannel(b, c), 0.01 * meanChannel(b, c)) << c;
  EXPECT_GT(meanChannel(a, 0), 1.3 * meanChannel(a, 1));
  const auto undivided = runCommand(quote(VDB_RENDER) + " " + quote(mantaflow) +
                                    " --grid albedo=color_r,color_g,color_b -o " + quote(refused) + flags);
  EXPECT_NE(undivided.status, 0);
  EXPECT_NE(undivided.err.find("outside [0,1]"), std::string::npos) << undivided.err;
  EXPECT_FALSE(std::filesystem::exists(refused));
}

// vdb_sggx_downsample writes the mapped albedo (the density-weighted mean of a constant: itself)
// and no Cd grid.
TEST(GridMappingCli, DownsampleWritesTheMappedGrid) {
  const TempDir dir;
  const std::string input = cubeWithCd(dir), out = dir.path("coarse.vdb");
  const auto r = runCommand(quote(VDB_SGGX_DOWNSAMPLE) + " --factor 2 --grid albedo=Cd " + quote(input) + " " + quote(out));
  ASSERT_EQ(r.status, 0) << r.err;
  const MediumPtr coarse = readMedium(out);
  ASSERT_TRUE(coarse->albedo);
  for (auto v = coarse->density->cbeginValueOn(); v; ++v)
    EXPECT_LT(test::maxAbsDifference(coarse->albedo->tree().getValue(v.getCoord()), openvdb::Vec3s(0.9f, 0.2f, 0.2f)), 1e-6);
  for (const auto& grid : coarse->other_grids) EXPECT_NE(grid->getName(), "Cd");
  EXPECT_EQ(r.err.find("dropped grid 'Cd'"), std::string::npos) << r.err;
}

TEST(GridMappingCli, InfoReportsTheMappedAlbedo) {
  const TempDir dir;
  const auto r = runCommand(quote(VDB_INFO) + " " + quote(cubeWithCd(dir)) + " --grid albedo=Cd --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"albedo\""), std::string::npos);
  EXPECT_EQ(r.out.find("\"Cd\""), std::string::npos);
}

// With no flag, the files of both programs render with their colour, detected: the Houdini cube
// and the Mantaflow cube give the images of their explicit rules, bit for bit, and each tool says in
// one note on stderr what it mapped; --from blender on the Houdini file maps nothing and says so.
TEST(GridMappingCli, DetectedConventionsRenderTheirColourWithANote) {
  const TempDir dir;
  const std::string flags = " --res 16 --spp 8 --env 1 --view -x --seed 3";
  const struct {
    std::string input, rule, note;
  } files[] = {{cubeWithCd(dir), "--grid albedo=Cd", "Houdini's Cd: read as --grid albedo=Cd (--from none"},
               {cubeWithMantaflowColour(dir), "--grid albedo=color_r,color_g,color_b/density",
                "Blender's smoke cache (Mantaflow): read as --grid albedo=color_r,color_g,color_b/density"}};
  for (const auto& f : files) {
    const std::string detected = dir.path("detected.exr"), ruled = dir.path("ruled.exr");
    const auto r = runCommand(quote(VDB_RENDER) + " " + quote(f.input) + " -o " + quote(detected) + flags);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("vdb_render: note: " + f.input + ": " + f.note), std::string::npos) << r.err;
    ASSERT_EQ(runCommand(quote(VDB_RENDER) + " " + quote(f.input) + " " + f.rule + " -o " + quote(ruled) + flags).status, 0);
    const RgbImage a = readRgbImage(detected), b = readRgbImage(ruled);
    EXPECT_EQ(a.pixels, b.pixels) << f.input;
    EXPECT_GT(meanChannel(a, 0), 1.3 * meanChannel(a, 1)) << f.input;
  }
  const std::string out = dir.path("preview.png");
  const auto blender = runCommand(quote(VDB_PREVIEW) + " " + quote(files[0].input) + " --from blender -o " + quote(out));
  ASSERT_EQ(blender.status, 0) << blender.err;
  EXPECT_NE(blender.err.find("vdb_preview: note: " + files[0].input + ": --from blender: none of its colour grids"),
            std::string::npos)
      << blender.err;
}

TEST(GridMappingCli, BadMappingsFailWithOneLineAndNoOutput) {
  const TempDir dir;
  const std::string input = cubeWithCd(dir), out = dir.path("out.exr");
  const struct {
    std::string flag, message;
    int status;
  } cases[] = {
      {"--grid albedo=colour", input + ": --grid albedo=colour: no grid named 'colour' (the file has Cd, density)", 1},
      {"--grid density=Cd", "--grid density=Cd: grid 'Cd' holds vec3s values, expected float", 1},
      {"--grid colour=Cd", "'colour' is not a grid of the medium contract", -1},
      {"--grid albedo=Cd --grid albedo=density", "albedo is already mapped", -1},
      {"--grid density=density:0", "is not a number > 0", -1},
      {"--from maya", "'maya': expected auto, blender, houdini or none", -1},
  };
  for (const auto& c : cases) {
    const auto r = runCommand(quote(VDB_RENDER) + " " + quote(input) + " " + c.flag + " --res 4 --spp 1 -o " + quote(out));
    EXPECT_NE(r.status, 0) << c.flag;
    if (c.status > 0) {
      EXPECT_EQ(r.status, c.status) << c.flag;
      EXPECT_EQ(lineCount(r.err), 1) << r.err;
    }
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.flag << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.flag;
  }
}

}  // namespace
}  // namespace vdbappear
