// vdb_exemplar_stack from the command line: the §7 pipeline through the tools, layouts, pipes and
// bad input.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kLobeCluster;
using test::kMakeMedium;
using test::kOptimize;
using test::kRender;
using test::kStack;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

// Four woven exemplars of 32 x 32 x 8 voxels and a 3 x 2 layout.
struct Blocks {
  TempDir dir;
  std::string blocks = dir.path("blocks.vdb"), out = dir.path("out.vdb");
  Blocks() {
    EXPECT_EQ(runCommand(kMakeMedium + " exemplars --count 4 --layout 3x2 --res 32 -o " + quote(blocks)).status, 0);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = dir.path(name);
    std::ofstream(path) << text;
    return path;
  }
};

void expectRefused(const Blocks& b, const std::string& command, const std::string& names) {
  const auto r = runCommand(command);
  EXPECT_NE(r.status, 0) << command;
  EXPECT_EQ(lineCount(r.err), 1) << command << "\n" << r.err;
  EXPECT_NE(r.err.find(names), std::string::npos) << "expected '" << names << "' in: " << r.err;
  EXPECT_FALSE(exists(b.out)) << command;
}

std::string metadataString(const Medium& medium, const char* key) {
  const auto value = medium.metadata.getMetadata<openvdb::StringMetadata>(key);
  return value ? value->value() : "";
}

TEST(ExemplarStackCli, HelpShowsTheCommandsAndExamples) {
  const auto r = runCommand(kStack + " --help");
  EXPECT_EQ(r.status, 0);
  for (const char* word : {"Usage:", "stack", "split", "assemble", "Examples:"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
  const auto assemble = runCommand(kStack + " assemble --help");
  EXPECT_NE(assemble.out.find("--layout"), std::string::npos);
}

// The §7 pipeline through the tools: stack, reduce to lobes and clusters, optimise the weights once,
// split, assemble; the model carries the clusters, lobes, weight factors and the exemplar set's name.
TEST(ExemplarStackCli, OneOptimisationOfTheStackServesTheAssembledModel) {
  const Blocks b;
  const std::string stacked = b.dir.path("stacked.vdb"), lobes = b.dir.path("lobes.vdb"),
                    optimised = b.dir.path("optimised.vdb"), reduced = b.dir.path("blocks_4x.vdb");
  ASSERT_EQ(runCommand(kStack + " stack --seed 5 " + quote(b.blocks) + " " + quote(stacked)).status, 0);
  ASSERT_EQ(runCommand(kLobeCluster + " -f 4 --lobes 2 --clusters 2 " + quote(stacked) + " " + quote(lobes)).status, 0);
  const auto opt = runCommand(kOptimize + " --resolution 16 --spp 4 --reference-spp 8 --iterations 1 --no-cache " +
                              quote(stacked) + " " + quote(lobes) + " " + quote(optimised));
  ASSERT_EQ(opt.status, 0) << opt.err;
  const auto split = runCommand(kStack + " split " + quote(optimised) + " " + quote(reduced));
  ASSERT_EQ(split.status, 0) << split.err;
  const auto assemble = runCommand(kStack + " assemble --report " + quote(b.dir.path("r.json")) + " " + quote(reduced) +
                                   " " + quote(b.out));
  ASSERT_EQ(assemble.status, 0) << assemble.err;

  const MediumPtr blocks = readMedium(reduced), model = readMedium(b.out);
  EXPECT_EQ(blocks->metadata.metaValue<openvdb::Vec3i>(metadata_names::kExemplarBlock), openvdb::Vec3i(8, 8, 2));
  EXPECT_EQ(metadataString(*blocks, metadata_names::kExemplarKind), "blocks");
  EXPECT_EQ(metadataString(*model, metadata_names::kExemplarKind), "model");
  EXPECT_EQ(metadataString(*model, metadata_names::kExemplarSet).rfind("xxh3:", 0), 0u);
  EXPECT_NE(metadataString(*model, metadata_names::kExemplarSet).find("blocks.vdb"), std::string::npos);
  EXPECT_FALSE(metadataString(*model, "weight_factors").empty());
  for (const char* grid : {"lobe0_weight", "lobe1_weight"})
    EXPECT_TRUE(findOtherGrid<openvdb::Vec3SGrid>(*model, grid)) << grid;
  for (const char* grid : {"cluster", "exemplar_layout"}) EXPECT_TRUE(findOtherGrid<openvdb::Int32Grid>(*model, grid)) << grid;
  EXPECT_FALSE(findOtherGrid<openvdb::Int32Grid>(*blocks, grid_names::kExemplarStacking));
  // The model spans its 3 x 2 blocks of 8 x 8 x 2 voxels.
  const openvdb::CoordBBox box = model->density->evalActiveVoxelBoundingBox();
  EXPECT_EQ(box.max().x(), 23);
  EXPECT_EQ(box.max().y(), 15);
}

TEST(ExemplarStackCli, JsonLayoutsAndPipes) {
  const Blocks b;
  const std::string two_d = b.write("two.json", "[[0, 1, 2], [3, -1, 0]]");
  const std::string three_d = b.write("three.json", "[[[0, 1]], [[2, 3]], [[1, 1]]]");
  ASSERT_EQ(runCommand(kStack + " assemble --layout " + quote(two_d) + " " + quote(b.blocks) + " " + quote(b.out)).status, 0);
  EXPECT_EQ(readMedium(b.out)->density->evalActiveVoxelBoundingBox().max().x(), 3 * 32 - 1);
  const std::string tall = b.dir.path("tall.vdb");
  ASSERT_EQ(runCommand(kStack + " assemble --layout " + quote(three_d) + " " + quote(b.blocks) + " " + quote(tall)).status, 0);
  EXPECT_GE(readMedium(tall)->density->evalActiveVoxelBoundingBox().max().z(), 2 * 8);  // in the third sheet

  // stack | split gives the blocks back; the input is not modified.
  const std::string bytes = test::readFileBytes(b.blocks);
  const std::string back = b.dir.path("back.vdb");
  const auto pipe = runCommand(kStack + " stack " + quote(b.blocks) + " - | " + kStack + " split - " + quote(back));
  ASSERT_EQ(pipe.status, 0) << pipe.err;
  EXPECT_EQ(readMedium(back)->density->activeVoxelCount(), readMedium(b.blocks)->density->activeVoxelCount());
  EXPECT_EQ(test::readFileBytes(b.blocks), bytes);

  // --shape 2x2x1: the four 32 x 32 x 8 sheets side by side in one layer; the report says so.
  const std::string flat = b.dir.path("flat.vdb");
  const auto stacked = runCommand(kStack + " stack --shape 2x2x1 --report - " + quote(b.blocks) + " " + quote(flat));
  ASSERT_EQ(stacked.status, 0) << stacked.err;
  EXPECT_EQ(nlohmann::json::parse(stacked.out)["shape"], nlohmann::json::array({2, 2, 1}));
  const openvdb::CoordBBox box = readMedium(flat)->density->evalActiveVoxelBoundingBox();
  EXPECT_EQ(box.max().x(), 63);
  EXPECT_EQ(box.max().y(), 63);
  EXPECT_LT(box.max().z(), 8);
}

// An instanced model renders the image of the model built voxel by voxel: same lookups, same per-block
// majorants, same random numbers; the image is the same to float rounding (compared at 1e-5).
void expectSameRender(const TempDir& dir, const std::string& built, const std::string& instanced,
                      const std::string& flags) {
  const std::string a = dir.path("built.exr"), b = dir.path("instanced.exr");
  const auto ra = runCommand(kRender + " " + quote(built) + " -o " + quote(a) + flags + " --report -");
  const auto rb = runCommand(kRender + " " + quote(instanced) + " -o " + quote(b) + flags + " --report -");
  ASSERT_EQ(ra.status, 0) << ra.err;
  ASSERT_EQ(rb.status, 0) << rb.err;
  const auto report_a = nlohmann::json::parse(ra.out), report_b = nlohmann::json::parse(rb.out);
  EXPECT_EQ(report_a["bounds"], report_b["bounds"]);
  EXPECT_EQ(report_a["majorant_voxels"], report_b["majorant_voxels"]);
  EXPECT_EQ(report_b["instanced_model_voxels"].get<std::uint64_t>(), readMedium(built)->density->activeVoxelCount());
  const ImageChannels x = readImageChannels(a), y = readImageChannels(b);
  ASSERT_EQ(x.values.size(), y.values.size());
  double largest = 0, worst = 0;
  for (std::size_t i = 0; i < x.values.size(); ++i) {
    largest = std::max(largest, double(std::abs(x.values[i])));
    worst = std::max(worst, double(std::abs(x.values[i] - y.values[i])));
  }
  EXPECT_GT(largest, 0.01);
  EXPECT_LE(worst, 1e-5 * largest) << flags;
}

TEST(ExemplarStackCli, InstancedModelsRenderTheBuiltModelsImage) {
  const Blocks b;
  const std::string layout = b.write("layout.json", "[[[0, 1, 2], [3, -1, 0]], [[2, 2, 1], [0, 3, 3]]]");
  const std::string built = b.dir.path("built.vdb"), instanced = b.dir.path("instanced.vdb");
  const std::string args = " --layout " + quote(layout) + " " + quote(b.blocks) + " ";
  ASSERT_EQ(runCommand(kStack + " assemble" + args + quote(built)).status, 0);
  ASSERT_EQ(runCommand(kStack + " assemble --instanced" + args + quote(instanced)).status, 0);
  EXPECT_LT(std::filesystem::file_size(instanced), std::filesystem::file_size(built));
  const std::string view = " --res 40x30 --spp 4 --seed 3 --camera-pos 9,-7,6 --camera-target 6,4,1 --fov 40 --ground";
  expectSameRender(b.dir, built, instanced, view);

  // An instanced model cannot emit yet (its majorant is the block set's): one error line, no image.
  const MediumPtr model = readMedium(instanced);
  auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*model, grid_names::kEmission, openvdb::Vec3s(0.0f));
  emission->tree().setValueOn(openvdb::Coord(0), openvdb::Vec3s(1.0f));
  openvdb::GridPtrVec grids = test::copyGrids(*model);
  grids.push_back(emission);
  const std::string glowing = b.dir.path("glowing.vdb"), image = b.dir.path("glowing.exr");
  test::writeRawVdb(glowing, grids, model->metadata);
  const auto refused = runCommand(kRender + " " + quote(glowing) + " -o " + quote(image) + view);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("grid 'emission': an instanced model cannot emit yet"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(image));

  // Reduced, multi-lobe blocks (the lobe, weight and cluster grids are read through the layout too).
  const std::string lobes = b.dir.path("lobes.vdb"), reduced = b.dir.path("reduced.vdb");
  const std::string stacked = b.dir.path("stacked.vdb");
  ASSERT_EQ(runCommand(kStack + " stack " + quote(b.blocks) + " " + quote(stacked)).status, 0);
  ASSERT_EQ(runCommand(kLobeCluster + " -f 2 --lobes 2 --clusters 2 " + quote(stacked) + " " + quote(lobes)).status, 0);
  ASSERT_EQ(runCommand(kStack + " split " + quote(lobes) + " " + quote(reduced)).status, 0);
  const std::string reduced_args = " --layout " + quote(layout) + " " + quote(reduced) + " ";
  ASSERT_EQ(runCommand(kStack + " assemble" + reduced_args + quote(built)).status, 0);
  ASSERT_EQ(runCommand(kStack + " assemble --instanced" + reduced_args + quote(instanced)).status, 0);
  expectSameRender(b.dir, built, instanced, view + " --aov cluster");

  // Trilinear lookups would read across block borders, which the per-block majorant does not bound.
  const auto trilinear = runCommand(kRender + " " + quote(instanced) + " -o " + quote(b.out) + " --interp trilinear");
  EXPECT_NE(trilinear.status, 0);
  EXPECT_NE(trilinear.err.find("nearest"), std::string::npos) << trilinear.err;
  EXPECT_FALSE(exists(b.out));
}

TEST(ExemplarStackCli, NonsenseFlagsFailWithoutOutput) {
  const Blocks b;
  const std::string io = " " + quote(b.blocks) + " " + quote(b.out);
  for (const std::string flags : {"", "bogus", "stack", "stack --order abc", "stack --order 0,1,2", "stack --order 0,0,1,2",
                                  "stack --order 0,1,2,x", "stack --seed -1",
                                  "stack --shape 1x1x3", "stack --shape 2x2", "stack --shape 0x4x1", "stack --shape 2x2x1x", "split --order 0", "stack --bogus 1"}) {
    const std::string command = kStack + " " + flags + (flags == "" || flags == "stack" ? "" : io);
    const auto r = runCommand(command);
    EXPECT_NE(r.status, 0) << command;
    EXPECT_FALSE(exists(b.out)) << command;
  }
}

TEST(ExemplarStackCli, BadInputIsOneErrorLineAndNoOutput) {
  const Blocks b;
  const std::string out = " " + quote(b.out);
  const std::string absent = b.dir.path("absent.vdb");
  expectRefused(b, kStack + " stack " + quote(absent) + out, absent + ": no such file");

  const std::string cube = b.dir.path("cube.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cube --res 16 -o " + quote(cube)).status, 0);
  expectRefused(b, kStack + " stack " + quote(cube) + out, cube + ": no metadata 'exemplar_count'");
  expectRefused(b, kStack + " split " + quote(b.blocks) + out, b.blocks + ": metadata 'exemplar_kind' is blocks");

  const std::string stacked = b.dir.path("stacked.vdb");
  ASSERT_EQ(runCommand(kStack + " stack " + quote(b.blocks) + " " + quote(stacked)).status, 0);
  expectRefused(b, kStack + " assemble " + quote(stacked) + out, "exemplar_kind' is stacked");
  expectRefused(b, kStack + " assemble --layout " + quote(cube) + " " + quote(b.blocks) + out,
                cube + ": no grid 'exemplar_layout'");

  // Layouts from media of other blocks: another exemplar count, another block size.
  const std::string six = b.dir.path("six.vdb"), wide = b.dir.path("wide.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " exemplars --count 6 --res 32 -o " + quote(six)).status, 0);
  expectRefused(b, kStack + " assemble --layout " + quote(six) + " " + quote(b.blocks) + out,
                six + ": a layout of 6 exemplars; the block set " + b.blocks + " holds 4");
  ASSERT_EQ(runCommand(kMakeMedium + " exemplars --count 4 --yarns 8 --res 32 -o " + quote(wide)).status, 0);
  expectRefused(b, kStack + " assemble --layout " + quote(wide) + " " + quote(b.blocks) + out, "world units");
  // ... while the full set's layout serves its reduced blocks.
  const std::string reduced = b.dir.path("reduced.vdb"), reduced_stack = b.dir.path("reduced_stack.vdb");
  ASSERT_EQ(runCommand(quote(VDB_SGGX_DOWNSAMPLE) + " -f 4 " + quote(stacked) + " " + quote(reduced_stack)).status, 0);
  ASSERT_EQ(runCommand(kStack + " split " + quote(reduced_stack) + " " + quote(reduced)).status, 0);
  EXPECT_EQ(runCommand(kStack + " assemble --layout " + quote(b.blocks) + " " + quote(reduced) + " " +
                       quote(b.dir.path("ok.vdb"))).status, 0);

  // A stack reduced by a factor that does not divide the block side (8 voxels along z).
  const std::string by3 = b.dir.path("stacked_3x.vdb");
  ASSERT_EQ(runCommand(quote(VDB_SGGX_DOWNSAMPLE) + " -f 3 " + quote(stacked) + " " + quote(by3)).status, 0);
  expectRefused(b, kStack + " split " + quote(by3) + out, "reduced by a factor 3");

  // Layouts naming a missing exemplar, ragged or not JSON.
  expectRefused(b, kStack + " assemble --layout " + quote(b.write("far.json", "[[0, 7]]")) + " " + quote(b.blocks) + out,
                "block (1,0,0) names exemplar 7; the block set holds 0..3");
  expectRefused(b, kStack + " assemble --layout " + quote(b.write("ragged.json", "[[0, 1], [2]]")) + " " +
                       quote(b.blocks) + out, "ragged.json: sheet 0, row 1");
  expectRefused(b, kStack + " assemble --layout " + quote(b.write("text.json", "[[0, \"a\"]]")) + " " + quote(b.blocks) + out,
                "is not an exemplar id");
  expectRefused(b, kStack + " assemble --layout " + quote(b.write("junk.json", "[[0, 1")) + " " + quote(b.blocks) + out,
                "junk.json: not a JSON layout");

  // A model that cannot fit in memory (1000 x 1000 blocks of thousands of voxels each: billions of
  // voxels, hundreds of GB) is refused before it is built, with the way out.
  {
    std::string rows = "[";
    for (int j = 0; j < 1000; ++j) {
      rows += j ? ",[" : "[";
      for (int i = 0; i < 1000; ++i) rows += i ? ",1" : "1";
      rows += "]";
    }
    expectRefused(b, kStack + " assemble --layout " + quote(b.write("huge.json", rows + "]")) + " " + quote(b.blocks) + out,
                  "assemble it with --instanced");
  }

  // A truncated block set.
  const std::string truncated = b.dir.path("truncated.vdb");
  {
    const std::string bytes = test::readFileBytes(b.blocks);
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  expectRefused(b, kStack + " stack " + quote(truncated) + out, truncated);
}

}  // namespace
}  // namespace vdbappear
