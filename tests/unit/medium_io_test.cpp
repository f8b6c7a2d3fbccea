// Reading, validating and writing media (docs/medium.md).
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"
#include "support/scoped_environment.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sys/wait.h>
#include <unistd.h>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::Vec3s;
using test::TempDir;

MediumPtr smallMedium(std::uint64_t seed = 1, bool hg = false) {
  RandomMediumParams p;
  p.extent = 24;
  p.seed = seed;
  p.hg_g = hg;
  return makeRandomMedium(p);
}

// A coordinate of `medium` where density > 0.
Coord denseVoxel(const Medium& medium) {
  for (auto it = medium.density->cbeginValueOn(); it; ++it)
    if (*it > 0) return it.getCoord();
  throw std::logic_error("no dense voxel");
}

TEST(MediumIo, RoundTripKeepsEveryGridAndAppendsHistory) {
  TempDir dir;
  const MediumPtr original = smallMedium(1, /*hg=*/true);
  writeMedium(*original, dir.path("a.vdb"), "tool_a 0.1: tool_a x");
  const MediumPtr once = readMedium(dir.path("a.vdb"));
  EXPECT_TRUE(test::gridsMatch(*original->density, *once->density, 0));
  EXPECT_TRUE(test::gridsMatch(*original->albedo, *once->albedo, 0));
  EXPECT_TRUE(test::gridsMatch(*original->sggx_diag, *once->sggx_diag, 0));
  EXPECT_TRUE(test::gridsMatch(*original->sggx_offdiag, *once->sggx_offdiag, 0));
  EXPECT_TRUE(test::gridsMatch(*original->hg_g, *once->hg_g, 0));
  EXPECT_EQ(once->transform(), original->transform());
  EXPECT_EQ(once->metadata.metaValue<int>(metadata_names::kSchema), 1);
  EXPECT_EQ(once->metadata.metaValue<std::string>(metadata_names::kHistory), "tool_a 0.1: tool_a x");

  writeMedium(*once, dir.path("b.vdb"), "tool_b 0.1: tool_b y");
  const MediumPtr twice = readMedium(dir.path("b.vdb"));
  EXPECT_EQ(twice->metadata.metaValue<std::string>(metadata_names::kHistory),
            "tool_a 0.1: tool_a x\ntool_b 0.1: tool_b y");
  EXPECT_EQ(test::listFiles(dir.root()), (std::vector<std::string>{"a.vdb", "b.vdb"})) << "no temporary files left";
}

TEST(MediumIo, GreyAlbedoIsReadAsRgb) {
  TempDir dir;
  const MediumPtr medium = smallMedium();
  auto grey = openvdb::FloatGrid::create(0.25f);
  grey->setName("albedo");
  grey->setTransform(medium->transform().copy());
  for (auto it = medium->density->cbeginValueOn(); it; ++it) grey->tree().setValue(it.getCoord(), 0.5f + 0.001f * (it.getCoord().x() & 7));
  grey->tree().addTile(1, Coord(800, 0, 0), 0.75f, true);  // tiles convert too
  test::writeRawVdb(dir.path("grey.vdb"), {medium->density, grey});
  const MediumPtr read = readMedium(dir.path("grey.vdb"));
  ASSERT_TRUE(read->albedo);
  EXPECT_EQ(read->albedo->background(), Vec3s(0.25f));
  EXPECT_EQ(read->albedo->activeVoxelCount(), grey->activeVoxelCount());
  for (auto it = grey->cbeginValueOn(); it; ++it)
    ASSERT_EQ(read->albedo->tree().getValue(it.getCoord()), Vec3s(*it)) << it.getCoord();
}

TEST(MediumIo, DensityOnlyMediaFromOtherProgramsAreAccepted) {
  TempDir dir;
  const MediumPtr medium = smallMedium();
  test::writeRawVdb(dir.path("density.vdb"), {medium->density});  // no schema, no history
  const MediumPtr read = readMedium(dir.path("density.vdb"));
  EXPECT_FALSE(read->albedo);
  EXPECT_FALSE(read->hasSggx());
}

// One bad medium: how to spoil a valid one, and what the message must name.
struct BadMedium {
  std::string name;
  std::function<void(Medium&, openvdb::GridPtrVec&, openvdb::MetaMap&)> spoil;
  std::string grid;     // grid the message must name ("" for file-level problems)
  std::string message;  // a part of the message
};

std::vector<BadMedium> badMedia() {
  using Grids = openvdb::GridPtrVec;
  using Meta = openvdb::MetaMap;
  auto setDensity = [](float value) {
    return [value](Medium& m, Grids&, Meta&) { m.density->tree().setValue(denseVoxel(m), value); };
  };
  return {
      {"missing_density", [](Medium& m, Grids&, Meta&) { m.density->setName("rho"); }, "", "no grid named 'density'"},
      {"density_of_wrong_type",
       [](Medium& m, Grids& extra, Meta&) {
         m.density->setName("unused");
         auto wrong = openvdb::Vec3SGrid::create();
         wrong->setName("density");
         wrong->setTransform(m.transform().copy());
         extra.push_back(wrong);
       },
       "density", "holds vec3s values, expected float"},
      {"nan_density", setDensity(NAN), "density", "NaN"},
      {"infinite_density", setDensity(INFINITY), "density", "NaN or infinite"},
      {"negative_density", setDensity(-0.5f), "density", "negative density -0.5"},
      {"density_background", [](Medium& m, Grids&, Meta&) { m.density->tree().root().setBackground(1.0f, true); },
       "density", "background is 1"},
      {"empty_density", [](Medium& m, Grids&, Meta&) { m.density->clear(); }, "density", "empty grid"},
      {"all_zero_density",
       [](Medium& m, Grids&, Meta&) {
         for (auto it = m.density->beginValueOn(); it; ++it) it.setValue(0.0f);
       },
       "density", "no voxel with density > 0"},
      {"frustum_transform",
       [](Medium& m, Grids&, Meta&) {
         auto frustum = openvdb::math::Transform::createFrustumTransform(
             openvdb::BBoxd(openvdb::Vec3d(-12), openvdb::Vec3d(12)), 0.5, 2, 1);
         for (const auto& grid : m.grids()) std::const_pointer_cast<openvdb::GridBase>(grid)->setTransform(frustum);
       },
       "density", "not linear"},
      {"albedo_above_one",
       [](Medium& m, Grids&, Meta&) { m.albedo->tree().setValueOn(denseVoxel(m), Vec3s(0.5f, 1.5f, 0.5f)); },
       "albedo", "outside [0,1]"},
      {"albedo_nan_inactive_under_density",
       [](Medium& m, Grids&, Meta&) { m.albedo->tree().setValueOff(denseVoxel(m), Vec3s(NAN)); }, "albedo",
       "where density is"},
      {"non_spd_S",
       [](Medium& m, Grids&, Meta&) { m.sggx_offdiag->tree().setValueOn(denseVoxel(m), Vec3s(2.0f, 0, 0)); },
       "sggx_diag", "not positive definite"},
      {"infinite_S_inactive_under_density",
       [](Medium& m, Grids&, Meta&) { m.sggx_diag->tree().setValueOff(denseVoxel(m), Vec3s(INFINITY, 1, 1)); },
       "sggx_diag", "not positive definite"},
      {"offdiag_without_diag", [](Medium& m, Grids&, Meta&) { m.sggx_diag->setName("unused"); }, "sggx_offdiag",
       "without 'sggx_diag'"},
      {"transform_mismatch",
       [](Medium& m, Grids&, Meta&) { m.albedo->setTransform(openvdb::math::Transform::createLinearTransform(0.3)); },
       "albedo", "transform differs"},
      {"duplicate_grid",
       [](Medium& m, Grids& extra, Meta&) { extra.push_back(m.albedo->deepCopyGrid()); }, "albedo",
       "more than once"},
      {"hg_out_of_range",
       [](Medium& m, Grids& extra, Meta&) {
         auto g = openvdb::FloatGrid::create(0.0f);
         g->setName("hg_g");
         g->setTransform(m.transform().copy());
         g->tree().setValueOn(denseVoxel(m), 1.5f);
         extra.push_back(g);
       },
       "hg_g", "outside (-1,1)"},
      {"lobe_grid_of_wrong_type",
       [](Medium& m, Grids& extra, Meta&) {
         auto g = openvdb::FloatGrid::create(0.0f);
         g->setName("lobe0_diag");
         g->setTransform(m.transform().copy());
         extra.push_back(g);
       },
       "lobe0_diag", "expected vec3s"},
      {"schema_too_new", [](Medium&, Grids&, Meta& meta) { meta.insertMeta("schema", openvdb::Int32Metadata(2)); },
       "", "schema 2 is newer"},
      {"schema_not_int", [](Medium&, Grids&, Meta& meta) { meta.insertMeta("schema", openvdb::StringMetadata("1")); },
       "", "'schema' is not an int32"},
      {"hg_metadata_out_of_range",
       [](Medium&, Grids&, Meta& meta) { meta.insertMeta("hg_g", openvdb::FloatMetadata(1.0f)); }, "",
       "metadata 'hg_g'"},
  };
}

class BadMediumTest : public testing::TestWithParam<std::size_t> {};

TEST_P(BadMediumTest, FailsWithOneMessageNamingFileAndGrid) {
  const BadMedium bad = badMedia()[GetParam()];
  TempDir dir;
  const MediumPtr medium = smallMedium();
  openvdb::GridPtrVec extra;
  openvdb::MetaMap metadata;
  bad.spoil(*medium, extra, metadata);
  openvdb::GridPtrVec grids = test::copyGrids(*medium);
  grids.insert(grids.end(), extra.begin(), extra.end());
  const std::string path = dir.path(bad.name + ".vdb");
  test::writeRawVdb(path, grids, metadata);

  const std::string message = test::readMediumError(path);
  ASSERT_FALSE(message.empty()) << bad.name << ": accepted";
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  if (!bad.grid.empty()) {
    EXPECT_NE(message.find("grid '" + bad.grid + "'"), std::string::npos) << message;
  }
  EXPECT_NE(message.find(bad.message), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

INSTANTIATE_TEST_SUITE_P(Cases, BadMediumTest, testing::Range<std::size_t>(0, badMedia().size()),
                         [](const testing::TestParamInfo<std::size_t>& info) { return badMedia()[info.param].name; });

TEST(MediumIo, NonPositiveDefiniteSIsAcceptedWhereDensityIsZero) {
  TempDir dir;
  const MediumPtr medium = smallMedium();
  medium->sggx_diag->tree().setValueOn(Coord(500, 500, 500), Vec3s(0.0f));  // no density there
  test::writeRawVdb(dir.path("ok.vdb"), test::copyGrids(*medium));
  EXPECT_NO_THROW(readMedium(dir.path("ok.vdb")));
}

// The reported voxel is the smallest bad one in (x,y,z) order, with 1 thread or many.
TEST(MediumIo, FirstBadVoxelIsReportedWhateverTheThreadCount) {
  TempDir dir;
  RandomMediumParams p;
  p.extent = 64;  // centred on 0: spans several root children, whose order is not (x,y,z) order
  const MediumPtr medium = makeRandomMedium(p);
  std::vector<Coord> dense;
  for (auto it = medium->density->cbeginValueOn(); it; ++it)
    if (*it > 0) dense.push_back(it.getCoord());
  std::vector<Coord> spoiled;
  for (std::size_t k = dense.size() / 3; k < dense.size(); k += dense.size() / 7) spoiled.push_back(dense[k]);
  for (const Coord& c : spoiled) medium->density->tree().setValue(c, -1.0f);
  test::writeRawVdb(dir.path("bad.vdb"), test::copyGrids(*medium));
  const Coord first = *std::min_element(spoiled.begin(), spoiled.end());
  std::ostringstream expected;
  expected << "at voxel (" << first.x() << "," << first.y() << "," << first.z() << ")";
  for (int threads : {1, 2, 8}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const std::string message = test::readMediumError(dir.path("bad.vdb"));
    EXPECT_NE(message.find(expected.str()), std::string::npos) << threads << " threads: " << message;
  }
}

TEST(MediumIo, BadTileValuesAndBackgroundsAreReported) {
  TempDir dir;
  MediumPtr medium = smallMedium();
  medium->density->tree().addTile(1, Coord(800, 0, 0), -2.0f, true);
  test::writeRawVdb(dir.path("tile.vdb"), test::copyGrids(*medium));
  EXPECT_NE(test::readMediumError(dir.path("tile.vdb")).find("negative density -2 at tile (800,0,0)"), std::string::npos)
      << test::readMediumError(dir.path("tile.vdb"));

  medium = smallMedium();
  medium->sggx_offdiag->tree().root().setBackground(Vec3s(NAN), true);
  test::writeRawVdb(dir.path("background.vdb"), test::copyGrids(*medium));
  EXPECT_NE(test::readMediumError(dir.path("background.vdb")).find("grid 'sggx_offdiag': background is NaN or infinite"),
            std::string::npos)
      << test::readMediumError(dir.path("background.vdb"));

  medium = smallMedium();
  openvdb::MetaMap metadata;
  metadata.insertMeta("hg_g", openvdb::Int32Metadata(0));
  test::writeRawVdb(dir.path("meta.vdb"), test::copyGrids(*medium), metadata);
  EXPECT_NE(test::readMediumError(dir.path("meta.vdb")).find("metadata 'hg_g' is not a number"), std::string::npos);
}

// A few bytes of tiles in a file claim billions of voxels, which validation would voxelise: refused
// before that, under a limit the environment raises (io/resource_limits.h).
TEST(MediumIo, TilesBeyondTheVoxelLimitAreRefusedBeforeTheyAreVoxelised) {
  TempDir dir;
  MediumPtr medium = smallMedium();
  medium->density->tree().addTile(3, Coord(4096 * 4, 0, 0), 1.0f, true);  // a root tile: 4096^3 voxels
  test::writeRawVdb(dir.path("huge.vdb"), test::copyGrids(*medium));
  EXPECT_NE(test::readMediumError(dir.path("huge.vdb"))
                .find("huge.vdb: grid 'density': its active tiles cover 68719476736 voxels, more than the limit of "
                      "2147483648 (VDBAPPEAR_MAX_TILE_VOXELS raises it)"),
            std::string::npos)
      << test::readMediumError(dir.path("huge.vdb"));

  medium = smallMedium();
  medium->density->tree().addTile(2, Coord(1024, 0, 0), 1.0f, true);  // 128^3 = 2097152 voxels
  test::writeRawVdb(dir.path("tile.vdb"), {medium->density});  // density alone: valid wherever it is dense
  EXPECT_EQ(test::readMediumError(dir.path("tile.vdb")), "");
  {
    const test::ScopedEnvironment limit("VDBAPPEAR_MAX_TILE_VOXELS", "1000000");
    EXPECT_NE(test::readMediumError(dir.path("tile.vdb")).find("its active tiles cover 2097152 voxels, more than the limit of 1000000"),
              std::string::npos)
        << test::readMediumError(dir.path("tile.vdb"));
  }
  {
    const test::ScopedEnvironment nonsense("VDBAPPEAR_MAX_TILE_VOXELS", "lots");
    EXPECT_NE(test::readMediumError(dir.path("tile.vdb")).find("VDBAPPEAR_MAX_TILE_VOXELS='lots': expected a positive integer"),
              std::string::npos)
        << test::readMediumError(dir.path("tile.vdb"));
  }
}

TEST(MediumIo, UnnamedGridsAreRejected) {
  TempDir dir;
  const MediumPtr medium = smallMedium();
  openvdb::GridPtrVec grids = test::copyGrids(*medium);
  grids.push_back(openvdb::FloatGrid::create());
  test::writeRawVdb(dir.path("unnamed.vdb"), grids);
  EXPECT_NE(test::readMediumError(dir.path("unnamed.vdb")).find("a grid has no name"), std::string::npos);
}

TEST(MediumIo, InvalidMediaAreNeverWritten) {
  TempDir dir;
  const MediumPtr medium = smallMedium();
  medium->density->tree().setValue(denseVoxel(*medium), -1.0f);
  try {
    writeMedium(*medium, dir.path("out.vdb"), "test");
    FAIL() << "written";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("not written"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(test::listFiles(dir.root()).empty());
}

TEST(MediumIo, UnreadableFilesAreReportedByName) {
  TempDir dir;
  EXPECT_NE(test::readMediumError(dir.path("absent.vdb")).find("absent.vdb: no such file"), std::string::npos);
  EXPECT_NE(test::readMediumError(dir.root().string()).find("is a directory"), std::string::npos);
  std::ofstream(dir.path("empty.vdb")).close();
  EXPECT_NE(test::readMediumError(dir.path("empty.vdb")).find("empty.vdb: not a readable VDB file"), std::string::npos);
  std::ofstream(dir.path("text.vdb")) << "this is not a VDB file\n";
  EXPECT_NE(test::readMediumError(dir.path("text.vdb")).find("text.vdb: not a readable VDB file"), std::string::npos);
}

TEST(MediumIo, TruncatedFilesAreRejectedWhereverTheyEnd) {
  TempDir dir;
  writeMedium(*smallMedium(), dir.path("whole.vdb"), "test");
  const auto size = std::filesystem::file_size(dir.path("whole.vdb"));
  for (double keep : {0.02, 0.3, 0.6, 0.9, 0.99}) {
    const std::string cut = dir.path("cut.vdb");
    std::filesystem::copy_file(dir.path("whole.vdb"), cut, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(cut, std::uintmax_t(keep * double(size)));
    const std::string message = test::readMediumError(cut);
    EXPECT_EQ(message.rfind(cut + ": ", 0), 0u) << "kept " << keep << ": '" << message << "'";
  }
}

TEST(AtomicFile, FailedWriteLeavesTheOldFileAndNoLitter) {
  TempDir dir;
  const std::string target = dir.path("out.vdb");
  std::ofstream(target) << "old";
  {
    AtomicFile output(target);
    std::ofstream(output.temporaryPath()) << "partial";
    // no commit: as if an exception left the scope
  }
  EXPECT_EQ(test::listFiles(dir.root()), std::vector<std::string>{"out.vdb"});
  std::ifstream in(target);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
  EXPECT_THROW(AtomicFile(dir.path("missing/out.vdb")), MediumError);
}

// A process interrupted in the middle of a write leaves the old file and no temporary: the handler
// that AtomicFile installs removes it, then the process ends by the signal as before.
TEST(AtomicFile, InterruptedWriteLeavesTheOldFileAndNoLitter) {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    TempDir dir;
    const std::string target = dir.path("out.vdb");
    std::ofstream(target) << "old";
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      AtomicFile output(target);
      std::ofstream(output.temporaryPath()) << "partial";
      raise(signal_number);
      _exit(0);  // not reached: the handler re-raises with the default action
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number) << "signal " << signal_number;
    EXPECT_EQ(test::listFiles(dir.root()), std::vector<std::string>{"out.vdb"}) << "signal " << signal_number;
    std::ifstream in(target);
    std::string content;
    in >> content;
    EXPECT_EQ(content, "old");
  }
}

TEST(MediumIo, HistoryLineQuotesArgumentsForTheShell) {
  const char* argv[] = {"/some/path/vdb_x", "--flag", "a b", "it's", "-"};
  const std::string line = historyLine("vdb_x", 5, argv);
  EXPECT_NE(line.find("vdb_x "), std::string::npos);
  EXPECT_NE(line.find(": vdb_x --flag 'a b' 'it'\\''s' -"), std::string::npos) << line;
}

}  // namespace
}  // namespace vdbappear
