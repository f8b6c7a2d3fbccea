// SH light grid files (docs/medium.md §11) and the grids' robustness: what the reader refuses,
// with one message naming the file and the grid, and lookups at points outside the box or not
// finite.
#include "libvdbappear/io/sh_light_grid_file.h"
#include "libvdbappear/lightgrid/adaptive_sh_grid.h"
#include "libvdbappear/lightgrid/sh_light_grid.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/util/error.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

namespace vdbappear {
namespace {

const PolygonLight kSquare{{Vec3(-1, -1, 1.5), Vec3(-1, 1, 1.5), Vec3(1, 1, 1.5), Vec3(1, -1, 1.5)}, Vec3(1, 0.5, 0.25)};

ShLightGrid smallGrid() {
  return ShLightGrid::evaluate({kSquare}, 2, ShGridLayout::covering(Vec3(-1, -1, -1), Vec3(1, 1, 1), 3), nullptr);
}

// Writes a good grid, lets `corrupt` change its grids and metadata, writes them back.
std::string corruptedFile(const test::TempDir& dir, const std::function<void(openvdb::GridPtrVec&, openvdb::MetaMap&)>& corrupt) {
  const std::string path = dir.path("grid.vdb");
  writeShLightGrid(smallGrid(), path, "test");
  openvdb::GridPtrVecPtr grids;
  openvdb::MetaMap::Ptr metadata;
  {
    openvdb::io::File file(path);
    file.open(false);
    grids = file.getGrids();
    metadata = file.getMetadata();
  }
  corrupt(*grids, *metadata);
  openvdb::io::File(path).write(*grids, *metadata);
  return path;
}

openvdb::GridBase::Ptr& gridNamed(openvdb::GridPtrVec& grids, const std::string& name) {
  for (auto& g : grids)
    if (g->getName() == name) return g;
  throw std::runtime_error("no grid " + name);
}

void expectRefused(const std::string& path, const std::string& expected) {
  try {
    readShLightGrid(path);
    ADD_FAILURE() << "read without complaint; expected: " << expected;
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("grid.vdb"), std::string::npos) << e.what();
  }
}

TEST(ShLightGridFile, ReaderRefusesMalformedFiles) {
  openvdb::initialize();
  test::TempDir dir;
  // The untouched file reads back (the corruptions below are the only difference).
  EXPECT_EQ(readShLightGrid(corruptedFile(dir, [](auto&, auto&) {}))->nodeCount(), 27u);
  expectRefused(corruptedFile(dir,
                              [](openvdb::GridPtrVec& grids, openvdb::MetaMap&) {
                                grids.erase(std::find(grids.begin(), grids.end(), gridNamed(grids, "sh_grad_b_8")));
                              }),
                "grid 'sh_grad_b_8' is missing");
  expectRefused(corruptedFile(dir,
                              [](openvdb::GridPtrVec&, openvdb::MetaMap& meta) {
                                meta.removeMeta("sh_levels");
                                meta.insertMeta("sh_levels", openvdb::Int64Metadata(0));
                              }),
                "'sh_levels' metadata is int64, expected int32");
  // A rotated map is linear but not axis-aligned: the lattice would be read wrongly.
  expectRefused(corruptedFile(dir,
                              [](openvdb::GridPtrVec& grids, openvdb::MetaMap&) {
                                auto rotated = grids[0]->transform().copy();
                                rotated->preRotate(0.3, openvdb::math::Z_AXIS);
                                for (auto& g : grids) g->setTransform(rotated);
                              }),
                "grid 'sh_0': expected a uniform scale-and-translate transform");
  expectRefused(corruptedFile(dir,
                              [](openvdb::GridPtrVec& grids, openvdb::MetaMap&) {
                                auto& grid = gridNamed(grids, "sh_grad_r_1");
                                auto moved = grid->transform().copy();
                                moved->postTranslate(openvdb::Vec3d(0.1, 0, 0));
                                grid->setTransform(moved);
                              }),
                "grid 'sh_grad_r_1': its transform differs from 'sh_0'");
  expectRefused(corruptedFile(dir,
                              [](openvdb::GridPtrVec& grids, openvdb::MetaMap&) {
                                auto g = openvdb::gridPtrCast<openvdb::Vec3SGrid>(gridNamed(grids, "sh_grad_g_0"));
                                g->tree().setValueOff(openvdb::Coord(1, 1, 1));
                              }),
                "grid 'sh_grad_g_0': its nodes differ from 'sh_0'");
}

// A hand-made adaptive file with two nodes far apart must be refused at once, not make the reader
// list 2^57 base cells.
TEST(ShLightGridFile, AdaptiveGridWithMissingBaseNodesIsRefusedQuickly) {
  ShLighting node(shCount(1));
  std::vector<std::pair<LatticeIndex, ShLighting>> nodes = {{{0, 0, 0}, node}, {{1048574, 1048574, 1048574}, node}};
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(AdaptiveShGrid::fromNodes(1, ShLattice{Vec3::Zero(), 1.0, 1}, nodes), std::invalid_argument);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

// contains() is the grid's box (to rounding), for uniform and adaptive grids; a lookup at a point
// that is not finite gives zeros instead of reading outside the nodes.
TEST(ShLightGridFile, GridsKnowTheirBoxAndSurviveNonFinitePoints) {
  const ShLightGrid uniform = smallGrid();
  AdaptiveGridOptions options;
  options.base_resolution = 3;
  options.max_level = 1;
  const AdaptiveShGrid adaptive = AdaptiveShGrid::build({kSquare}, 2, Vec3(-1, -1, -1), Vec3(1, 1, 1), options, nullptr);
  for (const ShGridLookup* grid : {static_cast<const ShGridLookup*>(&uniform), static_cast<const ShGridLookup*>(&adaptive)}) {
    EXPECT_TRUE(grid->contains(Vec3(0, 0, 0)));
    EXPECT_TRUE(grid->contains(Vec3(1, 1, 1)));
    EXPECT_TRUE(grid->contains(Vec3(-1, 1, -1)));
    EXPECT_FALSE(grid->contains(Vec3(1.01, 0, 0)));
    EXPECT_FALSE(grid->contains(Vec3(0, -1.01, 0)));
    EXPECT_FALSE(grid->contains(Vec3(0, 0, NAN)));
    for (const Vec3& bad : {Vec3(NAN, 0, 0), Vec3(0, INFINITY, 0)}) {
      const std::vector<Vec3> coeffs = grid->interpolate(bad, CellInterpolation::kHermite);
      ASSERT_EQ(coeffs.size(), std::size_t(shCount(2)));
      for (const Vec3& c : coeffs) EXPECT_TRUE(c.isZero());
    }
  }
}

TEST(ShLightGridFile, LayoutRefusesTooManyNodesAndInfiniteBoxes) {
  EXPECT_THROW(ShGridLayout::withSpacing(Vec3::Zero(), Vec3::Ones(), 1e-12), std::invalid_argument);
  EXPECT_THROW(ShGridLayout::withSpacing(Vec3::Zero(), Vec3(1, INFINITY, 1), 0.1), std::invalid_argument);
  EXPECT_THROW(ShGridLayout::withSpacing(Vec3::Zero(), Vec3::Ones(), INFINITY), std::invalid_argument);
  EXPECT_EQ(ShGridLayout::withSpacing(Vec3::Zero(), Vec3(1, 0.5, 0.2), 0.25).nodes, Eigen::Vector3i(5, 3, 2));
}

}  // namespace
}  // namespace vdbappear
