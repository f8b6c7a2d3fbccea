// vdb_make_medium and vdb_preview from the command line: kinds, flags, determinism, errors, images.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/phase_tables.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kMakeMedium;
using test::kPreview;
using test::quote;
using test::runCommand;
using test::TempDir;

const std::vector<std::string> kKinds{"twill", "velvet", "hairy-ball", "cube", "sphere",
                                      "slab",  "cloud",  "exemplars",  "random"};

TEST(MakeMediumCli, ListsEveryKind) {
  const auto list = runCommand(kMakeMedium + " --list");
  ASSERT_EQ(list.status, 0);
  for (const std::string& kind : kKinds) EXPECT_NE(list.out.find(kind + " "), std::string::npos) << kind;
  const auto help = runCommand(kMakeMedium + " --help");
  EXPECT_NE(help.out.find("Examples:"), std::string::npos);
  EXPECT_NE(help.out.find("--pattern"), std::string::npos);
}

// OpenVDB stamps each file with a fresh UUID: compare contents, not bytes.
TEST(MakeMediumCli, EveryKindIsDeterministicUnderASeed) {
  TempDir dir;
  for (const std::string& kind : kKinds) {
    const std::string res = kind == "exemplars" ? " --res 16" : " --res 24";
    const std::string a = dir.path(kind + "_a.vdb"), b = dir.path(kind + "_b.vdb");
    ASSERT_EQ(runCommand(kMakeMedium + " " + kind + res + " --seed 5 -j 1 -o " + quote(a)).status, 0) << kind;
    ASSERT_EQ(runCommand(kMakeMedium + " " + kind + res + " --seed 5 -o " + quote(b)).status, 0) << kind;
    const MediumPtr ma = readMedium(a), mb = readMedium(b);
    EXPECT_TRUE(test::gridsMatch(*ma->density, *mb->density, 0)) << kind;
    if (ma->albedo) EXPECT_TRUE(test::gridsMatch(*ma->albedo, *mb->albedo, 0)) << kind;
    if (ma->sggx_diag) EXPECT_TRUE(test::gridsMatch(*ma->sggx_diag, *mb->sggx_diag, 0)) << kind;
    if (ma->sggx_offdiag) EXPECT_TRUE(test::gridsMatch(*ma->sggx_offdiag, *mb->sggx_offdiag, 0)) << kind;
  }
}

TEST(MakeMediumCli, KindFlagsReachTheMedium) {
  TempDir dir;
  const std::string out = dir.path("m.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cube --res 8 --density 3 --albedo 0.2,0.4,0.6 --phase hg --g 0.5 -o " +
                       quote(out)).status, 0);
  MediumPtr m = readMedium(out);
  EXPECT_FLOAT_EQ(m->density->tree().getValue(openvdb::Coord(4)), 3.0f);
  EXPECT_FLOAT_EQ(m->albedo->tree().getValue(openvdb::Coord(4))[2], 0.6f);
  EXPECT_NEAR(*hgGMetadata(m->metadata), 0.5, 1e-6);
  ASSERT_EQ(runCommand(kMakeMedium + " twill --res 32 --yarns 2 --layers 2 -o " + quote(out)).status, 0);
  m = readMedium(out);
  const openvdb::CoordBBox box = m->density->evalActiveVoxelBoundingBox();
  EXPECT_GT(box.max().z(), 16) << "two layers";
  ASSERT_EQ(runCommand(kMakeMedium + " exemplars --res 16 --count 3 --layout 4x2 -o " + quote(out)).status, 0);
  m = readMedium(out);
  EXPECT_EQ(m->metadata.metaValue<int>(metadata_names::kExemplarCount), 3);
  ASSERT_EQ(m->other_grids.size(), 1u);
  EXPECT_EQ(m->other_grids[0]->activeVoxelCount(), 8u);
}

TEST(MakeMediumCli, RefusesBadKindsFlagsAndEmptyMediaWithoutOutput) {
  TempDir dir;
  const std::string out = dir.path("x.vdb");
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases{
      {"velvetish", "unknown kind 'velvetish'"},
      {"random --res 16 --block-fill 0", "not written"},
      {"random --res 16 --layers 3", "--layers does not apply to kind 'random' (only to twill)"},
      {"cloud --roughness 0.2", "--roughness does not apply to kind 'cloud'"},
      {"cube --g 0.5", "--g needs --phase hg"},
      {"twill --pattern jacquard", "jacquard"},
      {"twill --pattern twill --harness 2", "at least 3 harnesses"},
      {"exemplars --yarns 6", "multiple of 4"},
      {"exemplars --layout 8by8", "expected WxH"},
      {"exemplars --layout 8x8foo", "expected WxH"},
      {"cube --albedo 0.5,0.6", "1 value (grey) or 3"},
      {"twill --pattern plain --harness 3", "--harness needs --pattern twill or satin"},
      {"twill --pattern satin --harness 6", "no regular satin with 6 harnesses"},
      {"cube --albedo 1.5", "1.5"},
      {"cube --res 2", "--res"},
      {"cube --seed -1", "--seed"},
  };
  for (const Case& c : cases) {
    const auto r = runCommand(kMakeMedium + " " + c.args + " -o " + quote(out));
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
    EXPECT_FALSE(exists(out)) << c.args;
  }
  const auto no_output = runCommand(kMakeMedium + " cube");
  EXPECT_NE(no_output.err.find("no output"), std::string::npos) << no_output.err;
}

// The similarity work's inputs: a shape with a tabulated phase function, a cloud with per-voxel g.
TEST(MakeMediumCli, TabulatedPhaseAndPerVoxelG) {
  TempDir dir;
  {
    std::ofstream(dir.path("table.txt")) << "1 2 3 4\n";
  }
  const std::string cube = dir.path("cube.vdb"), cloud = dir.path("cloud.vdb");
  auto r = runCommand(kMakeMedium + " cube --res 8 --phase-table " + quote(dir.path("table.txt")) + " -o " + quote(cube));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto tables = readPhaseTables(*readMedium(cube));
  ASSERT_EQ(tables.size(), 1u);
  EXPECT_EQ(tables[0], (std::vector<double>{1, 2, 3, 4}));
  r = runCommand(kMakeMedium + " cube --res 8 --phase hg --phase-table " + quote(dir.path("table.txt")) + " -o " + quote(cube + "2"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--phase-table replaces --phase"), std::string::npos) << r.err;

  r = runCommand(kMakeMedium + " cloud --res 24 --g 0.95 --g-edge 0.6 -o " + quote(cloud));
  ASSERT_EQ(r.status, 0) << r.err;
  const MediumPtr medium = readMedium(cloud);
  ASSERT_TRUE(medium->hg_g);
  EXPECT_FALSE(hgGMetadata(medium->metadata));
  float lo = 1, hi = -1;
  for (auto g = medium->hg_g->cbeginValueOn(); g; ++g) lo = std::min(lo, *g), hi = std::max(hi, *g);
  EXPECT_GE(lo, 0.6f);
  EXPECT_LE(hi, 0.95f + 1e-6f);
  EXPECT_GT(hi - lo, 0.2f);
}

TEST(MakeMediumCli, PipesIntoThePreview) {
  TempDir dir;
  const std::string png = dir.path("twill.png");
  const auto r = runCommand(kMakeMedium + " twill --res 32 -o - | " + kPreview + " - --width 64 -o " + quote(png));
  ASSERT_EQ(r.status, 0) << r.err;
  auto input = OIIO::ImageInput::open(png);
  ASSERT_TRUE(input);
  EXPECT_EQ(input->spec().width, 64);
  EXPECT_EQ(input->spec().nchannels, 3);
}

TEST(PreviewCli, BadInputIsOneLineAndNoImage) {
  TempDir dir;
  const std::string png = dir.path("out.png");
  auto r = runCommand(kPreview + " " + quote(dir.path("missing.vdb")) + " -o " + quote(png));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("missing.vdb"), std::string::npos) << r.err;
  EXPECT_FALSE(exists(png));
  const std::string medium = dir.path("m.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " cube --res 8 -o " + quote(medium)).status, 0);
  r = runCommand(kPreview + " " + quote(medium) + " -o " + quote(dir.path("out.unknownformat")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("out.unknownformat"), std::string::npos) << r.err;
  EXPECT_EQ(test::listFiles(dir.path("")).size(), 1u) << "only the medium: no image, no temporary file";
}

}  // namespace
}  // namespace vdbappear
