// The parts reader (io/mapped_vdb_file.h, io/slab_tree_index.h) against OpenVDB's own whole read of
// the same file: every part's leaves bit for bit, the tiles, the counts, over grids that span several
// upper nodes (negative coordinates, tiles at every level, inactive values off the background), for
// each compression OpenVDB writes, half floats, with and without the file's table of leaf sizes; and
// the files it refuses.
#include "libvdbappear/io/mapped_vdb_file.h"
#include "libvdbappear/io/slab_tree_index.h"
#include "libvdbappear/util/error.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

float valueAt(const Coord& c, float) { return 0.001f * float(c.x()) - 0.37f * float(c.y() % 7) + 0.011f * float(c.z()); }
openvdb::Vec3s valueAt(const Coord& c, const openvdb::Vec3s&) {
  return openvdb::Vec3s(valueAt(c, 0.0f), 1.0f / float(1 + std::abs(c.y())), float(c.z() % 5));
}

// Leaves in three upper nodes (one at negative x, one at negative y), inactive values off the
// background, and tiles at each level: 8^3 active and inactive-off-background in a lower node, an
// active 128^3 one in an upper node, an active 4096^3 one at the root.
template <typename GridT>
typename GridT::Ptr scatteredGrid(const std::string& name, typename GridT::ValueType background) {
  using ValueT = typename GridT::ValueType;
  auto grid = GridT::create(background);
  grid->setName(name);
  auto& tree = grid->tree();
  std::mt19937 rng(7);
  for (const Coord& corner : {Coord(-5000, 3, -7), Coord(0, 0, 0), Coord(4200, -9000, 17)})
    for (int i = 0; i < 3000; ++i) {
      const Coord c = corner + Coord(int(rng() % 300), int(rng() % 200), int(rng() % 150));
      tree.setValueOn(c, valueAt(c, ValueT()));
      if (i % 5 == 0) tree.setValueOff(c + Coord(1, 0, 0), valueAt(c, ValueT()) * 2.0f);
    }
  tree.fill(CoordBBox(Coord(1024, 1024, 1024), Coord(1031, 1031, 1031)), valueAt(Coord(3), ValueT()), true);
  tree.fill(CoordBBox(Coord(1040, 1024, 1024), Coord(1047, 1031, 1031)), valueAt(Coord(5), ValueT()), false);
  tree.fill(CoordBBox::createCube(Coord(2048, 2048, 2048), 128), valueAt(Coord(7), ValueT()), true);
  tree.fill(CoordBBox::createCube(Coord(-8192, 0, 0), 4096), valueAt(Coord(9), ValueT()), true);
  return grid;
}

// The part holds exactly the whole grid's leaves in `box` (whole leaves), with the same masks and
// bits, and no tile.
template <typename GridT>
::testing::AssertionResult sameLeavesIn(const GridT& whole, const GridT& part, const CoordBBox& box, bool with_tiles = false) {
  using ValueT = typename GridT::ValueType;
  if (!(part.background() == whole.background())) return ::testing::AssertionFailure() << "backgrounds differ";
  std::size_t inside = 0;
  for (auto leaf = whole.tree().cbeginLeaf(); leaf; ++leaf) {
    if (!box.hasOverlap(leaf->getNodeBoundingBox())) continue;
    ++inside;
    const auto* other = part.tree().probeConstLeaf(leaf->origin());
    if (!other) return ::testing::AssertionFailure() << "no leaf at " << leaf->origin() << " in " << box;
    if (other->getValueMask() != leaf->getValueMask())
      return ::testing::AssertionFailure() << "masks differ at " << leaf->origin();
    if (std::memcmp(other->buffer().data(), leaf->buffer().data(), sizeof(ValueT) * leaf->SIZE) != 0)
      return ::testing::AssertionFailure() << "values differ in the leaf at " << leaf->origin();
  }
  if (part.tree().leafCount() != inside)
    return ::testing::AssertionFailure() << part.tree().leafCount() << " leaves read, " << inside << " in " << box;
  if (!with_tiles && part.tree().activeTileCount() != 0) return ::testing::AssertionFailure() << "the part holds tiles";
  return ::testing::AssertionSuccess();
}

// tiles() holds every tile of the whole grid above the leaf level that is active or off the
// background, and nothing else.
template <typename GridT>
::testing::AssertionResult sameTiles(const GridT& whole, const GridT* tiles) {
  std::size_t count = 0;
  auto tile = whole.tree().cbeginValueAll();
  tile.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) {
    if (!tile.isValueOn() && *tile == whole.background()) continue;
    ++count;
    if (!tiles || !(tiles->tree().getValue(tile.getCoord()) == *tile) || tiles->tree().isValueOn(tile.getCoord()) != tile.isValueOn())
      return ::testing::AssertionFailure() << "tile at " << tile.getCoord() << " (level " << tile.getLevel() << ") missing";
  }
  std::size_t indexed = 0;
  if (tiles) {
    auto t = tiles->tree().cbeginValueAll();
    t.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
    for (; t; ++t) indexed += t.isValueOn() || !(*t == tiles->background());
  }
  if (indexed != count) return ::testing::AssertionFailure() << indexed << " tiles indexed, " << count << " in the grid";
  return ::testing::AssertionSuccess();
}

template <typename GridT>
void expectIndexReadsAsWhole(const MappedVdbFile& file, std::size_t index_of, const GridT& whole, const std::string& context) {
  SCOPED_TRACE(context + ", grid " + whole.getName());
  const SlabTreeIndex index(file, index_of);
  EXPECT_EQ(index.leafCount(), whole.tree().leafCount());
  EXPECT_EQ(index.activeVoxelCount(), whole.activeVoxelCount());
  std::set<Coord> origins, expected;
  index.forEachLeaf([&](const Coord& c) { origins.insert(c); });
  for (auto leaf = whole.tree().cbeginLeaf(); leaf; ++leaf) expected.insert(leaf->origin());
  EXPECT_EQ(origins, expected);
  EXPECT_TRUE(sameTiles(whole, static_cast<const GridT*>(index.tiles().get())));
  const int lo = std::numeric_limits<int>::min(), hi = std::numeric_limits<int>::max();
  for (const CoordBBox& box : {CoordBBox(Coord(-4992, lo, lo), Coord(-4977, hi, hi)),  // cuts a node
                               CoordBBox(Coord(0, lo, lo), Coord(7, hi, hi)),          // one slice
                               CoordBBox(Coord(120, lo, lo), Coord(263, hi, hi)),      // across nodes
                               CoordBBox(Coord(4200, lo, lo), Coord(4327, hi, hi)),
                               CoordBBox(Coord(0, 16, 8), Coord(127, 63, 55)),  // leaves in x but not in y or z
                               CoordBBox(Coord(lo, lo, lo), Coord(hi, hi, hi))}) {
    const auto part = openvdb::gridPtrCast<GridT>(index.readLeaves(box));
    ASSERT_TRUE(part);
    EXPECT_TRUE(sameLeavesIn(whole, *part, box));
    EXPECT_EQ(part->getName(), whole.getName());
    EXPECT_EQ(part->transform(), whole.transform());
  }
  const auto read_whole = openvdb::gridPtrCast<GridT>(index.readWhole());  // every leaf and tile
  ASSERT_TRUE(read_whole);
  EXPECT_TRUE(sameLeavesIn(whole, *read_whole, CoordBBox::inf(), /*with_tiles=*/true));
  EXPECT_TRUE(sameTiles(whole, read_whole.get()));
  EXPECT_EQ(read_whole->activeVoxelCount(), whole.activeVoxelCount());
}

TEST(SlabTreeIndex, ReadsEveryPartAsOpenVdbReadsTheWhole) {
  openvdb::initialize();
  test::TempDir dir;
  auto density = scatteredGrid<openvdb::FloatGrid>("density", 0.0f);
  auto level = scatteredGrid<openvdb::FloatGrid>("level", 3.0f);
  auto colour = scatteredGrid<openvdb::Vec3SGrid>("colour", openvdb::Vec3s(1.0f, 0.5f, 0.25f));
  colour->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  using openvdb::io::COMPRESS_ACTIVE_MASK, openvdb::io::COMPRESS_BLOSC, openvdb::io::COMPRESS_ZIP, openvdb::io::COMPRESS_NONE;
  for (const std::uint32_t compression : std::initializer_list<std::uint32_t>{
           COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK, COMPRESS_ZIP, COMPRESS_ACTIVE_MASK,
           COMPRESS_NONE})
    for (const bool half : {false, true}) {
      const std::string path = dir.path("scattered.vdb");
      for (auto& grid : std::initializer_list<openvdb::GridBase::Ptr>{density, level, colour}) grid->setSaveFloatAsHalf(half);
      {
        openvdb::io::File out(path);
        out.setCompression(compression);
        out.write({density, level, colour});
      }
      openvdb::io::File in(path);
      in.open(/*delayLoad=*/false);
      openvdb::GridPtrVec whole;
      for (const std::string name : {"density", "level", "colour"}) whole.push_back(in.readGrid(name));
      for (const auto sizes : {MappedVdbFile::LeafSizes::kIfPresent, MappedVdbFile::LeafSizes::kIgnore}) {
        const std::string context = openvdb::io::compressionToString(compression) + (half ? ", half floats" : "") +
                                    (sizes == MappedVdbFile::LeafSizes::kIgnore ? ", leaf sizes ignored" : "");
        const MappedVdbFile file(path, sizes);
        ASSERT_EQ(file.gridCount(), 3u);
        EXPECT_FALSE(file.whyNotInParts()) << *file.whyNotInParts();
        for (std::size_t i = 0; i < 3; ++i) {
          ASSERT_EQ(file.header(i)->getName(), whole[i]->getName());
          if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(whole[i])) expectIndexReadsAsWhole(file, i, *f, context);
          if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(whole[i])) expectIndexReadsAsWhole(file, i, *v, context);
        }
      }
    }
}

// A dense block of 32768 leaves: the index holds under 8 bytes a leaf (OpenVDB's delayed loading
// holds some 270).
TEST(SlabTreeIndex, HoldsAFewBytesANodeNotALeaf) {
  openvdb::initialize();
  test::TempDir dir;
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->denseFill(CoordBBox(Coord(0), Coord(255)), 1.0f, true);
  openvdb::io::File(dir.path("block.vdb")).write({grid});
  const MappedVdbFile file(dir.path("block.vdb"));
  const SlabTreeIndex index(file, 0);
  EXPECT_EQ(index.leafCount(), 32768u);
  EXPECT_LT(index.memoryBytes(), 8 * index.leafCount());
}

TEST(MappedVdbFile, NamesWhatItCannotReadInParts) {
  openvdb::initialize();
  test::TempDir dir;
  auto density = scatteredGrid<openvdb::FloatGrid>("density", 0.0f);

  {  // written as a stream: no grid offsets
    std::ofstream out(dir.path("stream.vdb"), std::ios::binary);
    openvdb::io::Stream(out).write({density});
  }
  EXPECT_EQ(MappedVdbFile(dir.path("stream.vdb")).whyNotInParts().value_or(""),
            "it was written as a stream, without the grids' places in the file");

  auto instance = density->copyGrid();  // shares the tree
  instance->setName("copy");
  openvdb::io::File(dir.path("instance.vdb")).write({density, instance});
  EXPECT_EQ(MappedVdbFile(dir.path("instance.vdb")).whyNotInParts().value_or(""),
            "grid 'copy' shares the tree of grid 'density'");

  std::ofstream(dir.path("text.vdb")) << "not a VDB file at all, but long enough to have a header";
  try {
    MappedVdbFile text(dir.path("text.vdb"));
    ADD_FAILURE() << "a text file was read";
  } catch (const MediumError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.path("text.vdb") + ": not a readable VDB file (", 0), 0u) << e.what();
  }

  openvdb::io::File(dir.path("whole.vdb")).write({density});
  const auto size = std::filesystem::file_size(dir.path("whole.vdb"));
  for (const double keep : {0.1, 0.5, 0.9, 0.999}) {  // truncated: refused at the open, naming file and grid
    std::filesystem::copy_file(dir.path("whole.vdb"), dir.path("cut.vdb"), std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(dir.path("cut.vdb"), std::uintmax_t(double(size) * keep));
    try {
      MappedVdbFile cut(dir.path("cut.vdb"));
      ADD_FAILURE() << "a file cut at " << keep << " was read";
    } catch (const MediumError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(dir.path("cut.vdb") + ": ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace vdbappear
