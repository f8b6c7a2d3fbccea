// Modularity (§7 of the downsampling paper): stacking exemplar blocks, splitting a reduced stack back
// into blocks and assembling models are exact rearrangements of voxels.
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/modularity/assembly.h"
#include "libvdbappear/modularity/stacking.h"
#include "libvdbappear/procedural/exemplar_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace vdbappear {
namespace {

using openvdb::Coord;
using test::gridsMatch;

constexpr int kSide = 32;  // voxels per block side along x and y; blocks are 32 x 32 x 8

MediumPtr exemplarBlocks(int count = 5) {
  ExemplarParams params;
  params.resolution = kSide;
  params.count = count;
  params.layout_width = 3;
  params.layout_height = 2;
  MediumPtr blocks = makeExemplars(params);
  blocks->source = "blocks.vdb";
  return blocks;
}

Coord blockSize(const Medium& medium) {
  const auto b = medium.metadata.metaValue<openvdb::Vec3i>(metadata_names::kExemplarBlock);
  return Coord(b.x(), b.y(), b.z());
}

// Block `a` of grid `x` and block `b` of grid `y` hold the same active voxels with the same values,
// bit for bit.
template <typename GridT>
::testing::AssertionResult sameBlock(const GridT& x, const Coord& a, const GridT& y, const Coord& b, const Coord& size) {
  auto in_x = x.getConstAccessor();
  auto in_y = y.getConstAccessor();
  for (int k = 0; k < size.z(); ++k)
    for (int j = 0; j < size.y(); ++j)
      for (int i = 0; i < size.x(); ++i) {
        const Coord local(i, j, k);
        const Coord p(a.x() * size.x(), a.y() * size.y(), a.z() * size.z()), q(b.x() * size.x(), b.y() * size.y(), b.z() * size.z());
        if (in_x.isValueOn(p + local) != in_y.isValueOn(q + local) ||
            (in_x.isValueOn(p + local) && !(in_x.getValue(p + local) == in_y.getValue(q + local))))
          return ::testing::AssertionFailure() << "grid '" << x.getName() << "' differs at " << (p + local) << " / "
                                               << (q + local);
      }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult sameBlock(const Medium& x, const Coord& a, const Medium& y, const Coord& b) {
  const Coord size = blockSize(x);
  for (auto result : {sameBlock(*x.density, a, *y.density, b, size), sameBlock(*x.albedo, a, *y.albedo, b, size),
                      sameBlock(*x.sggx_diag, a, *y.sggx_diag, b, size),
                      sameBlock(*x.sggx_offdiag, a, *y.sggx_offdiag, b, size)})
    if (!result) return result;
  return ::testing::AssertionSuccess();
}

void expectSameVoxels(const Medium& expected, const Medium& actual, double density_tolerance, double tolerance) {
  EXPECT_TRUE(gridsMatch(*expected.density, *actual.density, density_tolerance));
  ASSERT_EQ(bool(expected.albedo), bool(actual.albedo));
  ASSERT_EQ(bool(expected.sggx_diag), bool(actual.sggx_diag));
  if (expected.albedo) EXPECT_TRUE(gridsMatch(*expected.albedo, *actual.albedo, tolerance));
  if (expected.sggx_diag) EXPECT_TRUE(gridsMatch(*expected.sggx_diag, *actual.sggx_diag, tolerance));
  if (expected.sggx_offdiag) EXPECT_TRUE(gridsMatch(*expected.sggx_offdiag, *actual.sggx_offdiag, tolerance));
}

ExemplarLayout layout2x2(std::vector<int> ids) {
  ExemplarLayout layout;
  layout.width = 2;
  layout.height = 2;
  layout.depth = int(ids.size()) / 4;
  layout.ids = std::move(ids);
  return layout;
}

TEST(ExemplarStack, ShapeIsNearCubicWithAtMostOneIncompleteLayer) {
  for (int count : {1, 5, 6, 7, 8, 27, 120}) {
    const BlockCounts shape = stackShape(count, {32, 32, 8});
    const int layer = shape[0] * shape[1];
    EXPECT_GE(layer * shape[2], count) << count;
    EXPECT_LT(layer * (shape[2] - 1), count) << count << ": a whole layer left empty";
  }
  // Sheets lie side by side in one layer, as square as the count allows; cubes make a cube.
  EXPECT_EQ(stackShape(6, {64, 64, 16}), (BlockCounts{2, 3, 1}));
  EXPECT_EQ(stackShape(7, {64, 64, 16}), (BlockCounts{2, 4, 1}));
  EXPECT_EQ(stackShape(120, {64, 64, 16}), (BlockCounts{10, 12, 1}));
  EXPECT_EQ(stackShape(8, {16, 16, 16}), (BlockCounts{2, 2, 2}));
  EXPECT_EQ(stackShape(6, {64, 64, 40}), (BlockCounts{1, 2, 3}));
}

TEST(ExemplarStack, RandomOrderIsASeededPermutation) {
  StackOptions options;
  options.seed = 3;
  const std::vector<int> a = stackOrder(120, options), b = stackOrder(120, options);
  EXPECT_EQ(a, b);
  std::vector<int> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(120);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(sorted, identity);
  EXPECT_NE(a, identity);
  options.seed = 4;
  EXPECT_NE(stackOrder(120, options), a);
  options.order = StackOptions::Order::Given;
  options.permutation = {2, 0, 1};
  EXPECT_EQ(stackOrder(3, options), options.permutation);
  for (std::vector<int> bad : {std::vector<int>{0, 0, 1}, {0, 1}, {0, 1, 3}, {0, 1, 2, 3}}) {
    options.permutation = bad;
    EXPECT_THROW(stackOrder(3, options), std::invalid_argument);
  }
}

// Acceptance: each block of a model assembled from full-resolution blocks is its exemplar bit for bit.
TEST(ExemplarStack, AssembledBlocksEqualTheirExemplarsBitForBit) {
  const MediumPtr blocks = exemplarBlocks();
  const ExemplarLayout layout = layout2x2({3, 0, ExemplarLayout::kEmpty, 3, 1, 4, 2, 0});  // 2 x 2 x 2
  const MediumPtr model = assembleModel(*blocks, layout);
  const Coord size = blockSize(*model);
  ASSERT_EQ(size, blockSize(*blocks));
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int e = layout.at(i, j, k);
        if (e == ExemplarLayout::kEmpty)  // block 7 of the block set lies beyond its five exemplars: empty
          EXPECT_TRUE(sameBlock(*model->density, Coord(i, j, k), *blocks->density, Coord(7, 0, 0), size));
        else
          EXPECT_TRUE(sameBlock(*blocks, Coord(e, 0, 0), *model, Coord(i, j, k))) << "block " << Coord(i, j, k);
      }
  EXPECT_FALSE(sameBlock(*blocks, Coord(0, 0, 0), *model, Coord(0, 0, 0)));  // negative control: exemplar 3 is there
  const openvdb::CoordBBox box = model->density->evalActiveVoxelBoundingBox();  // nothing outside the 2 x 2 x 2 blocks
  EXPECT_TRUE(openvdb::CoordBBox(Coord(0), Coord(2 * size.x() - 1, 2 * size.y() - 1, 2 * size.z() - 1)).isInside(box))
      << box;
  EXPECT_EQ(model->metadata.metaValue<std::string>(metadata_names::kExemplarKind), "model");
  const auto stored = findOtherGrid<openvdb::Int32Grid>(*model, grid_names::kExemplarLayout);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->tree().getValue(Coord(0, 0, 1)), 1);
  EXPECT_FALSE(stored->tree().isValueOn(Coord(0, 1, 0)));
}

TEST(ExemplarStack, SplitUndoesStackBitForBit) {
  const MediumPtr blocks = exemplarBlocks();
  StackOptions options;
  options.seed = 11;
  const MediumPtr stacked = stackExemplars(*blocks, options);
  EXPECT_EQ(stacked->metadata.metaValue<std::string>(metadata_names::kExemplarKind), "stacked");
  EXPECT_EQ(stacked->density->activeVoxelCount(), blocks->density->activeVoxelCount());
  // Five 32x32x8 sheets lie side by side in a 2 x 3 layer of slots.
  const openvdb::CoordBBox box = stacked->density->evalActiveVoxelBoundingBox();
  EXPECT_LE(box.max().x(), 2 * kSide - 1);
  EXPECT_GE(box.max().y(), 2 * kSide);
  EXPECT_LT(box.max().z(), 8);
  const MediumPtr back = splitStacked(*stacked);
  expectSameVoxels(*blocks, *back, 0, 0);
  EXPECT_FALSE(findOtherGrid<openvdb::Int32Grid>(*back, grid_names::kExemplarStacking));
  EXPECT_TRUE(findOtherGrid<openvdb::Int32Grid>(*back, grid_names::kExemplarLayout));
  EXPECT_EQ(back->metadata.metaValue<std::string>(metadata_names::kExemplarKind), "blocks");
}

// Acceptance: stack, naive downsample by F, split, assemble = naive downsample by F of the assembled
// full-resolution model, to float rounding (the children of a coarse voxel lie in one block, summed
// in another order).
TEST(ExemplarStack, ReducedBlocksAssembleToTheReducedModel) {
  const MediumPtr blocks = exemplarBlocks();
  const ExemplarLayout layout = layout2x2({4, 1, 1, 0, 2, 2, 3, 4});
  for (int F : {2, 4, 8}) {
    SCOPED_TRACE(::testing::Message() << "F = " << F);
    const MediumPtr stacked = stackExemplars(*blocks, StackOptions{});
    const MediumPtr reduced_stack = downsampleNaive(*stacked, {F, SggxWeighting::Count}).medium;
    const MediumPtr reduced_blocks = splitStacked(*reduced_stack);
    EXPECT_EQ(blockSize(*reduced_blocks), Coord(kSide / F, kSide / F, 8 / F));
    const MediumPtr fast = assembleModel(*reduced_blocks, layout);
    const MediumPtr reference = downsampleNaive(*assembleModel(*blocks, layout), {F, SggxWeighting::Count}).medium;
    expectSameVoxels(*reference, *fast, 1e-4, 1e-5);  // density up to 40 per unit
    EXPECT_TRUE(reference->transform() == fast->transform());
    // Negative control: another layout of the same blocks is another model.
    const MediumPtr other = assembleModel(*reduced_blocks, layout2x2({4, 1, 1, 0, 2, 2, 4, 3}));
    EXPECT_FALSE(gridsMatch(*reference->albedo, *other->albedo, 1e-5));
  }
}

TEST(ExemplarStack, RefusesABlockSideTheFactorDoesNotDivide) {
  const MediumPtr stacked = stackExemplars(*exemplarBlocks(), StackOptions{});
  const MediumPtr reduced = downsampleNaive(*stacked, {3, SggxWeighting::Count}).medium;
  reduced->source = "stacked_3x.vdb";
  try {
    splitStacked(*reduced);
    FAIL() << "no error";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("stacked_3x.vdb"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("factor 3"), std::string::npos) << e.what();
  }
}

TEST(ExemplarStack, RefusesMediaOfTheWrongKindAndBrokenPlacements) {
  const MediumPtr blocks = exemplarBlocks();
  const MediumPtr stacked = stackExemplars(*blocks, StackOptions{});
  EXPECT_THROW(splitStacked(*blocks), MediumError);            // not stacked
  EXPECT_THROW(stackExemplars(*stacked, StackOptions{}), MediumError);  // already stacked
  EXPECT_THROW(assembleModel(*stacked, layout2x2({0, 1, 2, 3})), MediumError);
  EXPECT_THROW(assembleModel(*blocks, layout2x2({0, 1, 2, 5})), MediumError);  // exemplar 5 of 0..4

  Medium no_placement = *stacked;
  no_placement.other_grids.clear();
  EXPECT_THROW(splitStacked(no_placement), MediumError);

  Medium twice = *stacked;
  auto placement = findOtherGrid<openvdb::Int32Grid>(*stacked, grid_names::kExemplarStacking)->deepCopy();
  placement->tree().setValueOn(Coord(0, 0, 1), placement->tree().getValue(Coord(0, 0, 0)));
  twice.other_grids = {placement};
  EXPECT_THROW(splitStacked(twice), MediumError);

  Medium stray = *blocks;  // a voxel beyond the N blocks
  stray.density = blocks->density->deepCopy();
  stray.density->tree().setValueOn(Coord(5 * kSide + 3, 0, 0), 1.0f);
  EXPECT_THROW(stackExemplars(stray, StackOptions{}), MediumError);
}

}  // namespace
}  // namespace vdbappear
