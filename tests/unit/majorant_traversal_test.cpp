// The hierarchical majorant walk (medium/majorant_traversal.h): a walk that starts below the top
// of the tree, where the active voxels lie within one node of each level above, reports the
// segments of the walk from the top (the same majorants, ends equal up to the rounding of a
// node's exit time against the box's); and the start level is the lowest such level.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/medium/majorant_traversal.h"

#include "support/test_random.h"

#include <gtest/gtest.h>

#include <tuple>
#include <vector>

namespace vdbappear {
namespace {

using Segment = std::tuple<double, double, double>;

// A majorant grid with random values in [0.5, 2) at a fraction of the voxels of `box`.
openvdb::FloatGrid::Ptr randomMajorants(const openvdb::CoordBBox& box, test::TestRandom& random) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  auto accessor = grid->getAccessor();
  for (auto ijk = box.begin(); ijk; ++ijk)
    if (random.uniform() < 0.3 || *ijk == box.min() || *ijk == box.max())
      accessor.setValue(*ijk, float(0.5 + 1.5 * random.uniform()));
  return grid;
}

std::vector<Segment> segments(const MajorantRay& ray, const openvdb::FloatGrid& grid, int start_level) {
  std::vector<Segment> out;
  auto accessor = grid.getConstAccessor();
  forEachMajorantSegment(
      ray, accessor,
      [&](double t0, double t1, double sigma) {
        out.emplace_back(t0, t1, sigma);
        return true;
      },
      start_level);
  return out;
}

struct Case {
  openvdb::CoordBBox box;
  int start_level;  // expected
};

TEST(MajorantTraversal, StartingBelowTheTopGivesTheSegmentsOfTheWholeWalk) {
  const Case cases[] = {
      {openvdb::CoordBBox({0, 0, 0}, {7, 7, 7}), -1},        // one leaf: its voxels directly
      {openvdb::CoordBBox({8, 16, 0}, {13, 20, 5}), -1},     // one leaf off the origin
      {openvdb::CoordBBox({0, 0, 0}, {40, 9, 30}), 0},       // leaves of one internal node
      {openvdb::CoordBBox({120, 0, 0}, {135, 12, 7}), 1},    // two level-1 nodes of one level-2 node
      {openvdb::CoordBBox({-3, -2, 0}, {4, 5, 6}), 2},       // around the origin: every level splits
  };
  test::TestRandom random(31);
  for (const Case& c : cases) {
    const auto grid = randomMajorants(c.box, random);
    const openvdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
    const int start = majorantWalkStartLevel(grid->tree(), active);
    EXPECT_EQ(start, c.start_level) << c.box;
    const openvdb::BBoxd box(active.min().asVec3d(), active.max().asVec3d() + openvdb::Vec3d(1.0));
    int walked = 0;
    for (int k = 0; k < 300; ++k) {
      const Vec3 o = toVec3(box.min()) - Vec3::Constant(2) +
                     Vec3(random.uniform(), random.uniform(), random.uniform()).cwiseProduct(toVec3(box.extents()) + Vec3::Constant(4));
      const Vec3 d = k % 10 == 0 ? Vec3(0, 0, 1) : random.direction();  // axis-aligned rays too
      MajorantRay ray(openvdb::Vec3d(o.x(), o.y(), o.z()), openvdb::Vec3d(d.x(), d.y(), d.z()), 0.0, 1e3);
      if (!ray.clip(box) || !(ray.t1() > ray.t0())) continue;
      ++walked;
      const std::vector<Segment> whole = segments(ray, *grid, 2);
      const std::vector<Segment> from_start = segments(ray, *grid, start);
      ASSERT_EQ(from_start.size(), whole.size()) << c.box << " ray " << k;
      for (std::size_t i = 0; i < whole.size(); ++i) {
        const auto [a0, a1, a_sigma] = from_start[i];
        const auto [b0, b1, b_sigma] = whole[i];
        EXPECT_EQ(a_sigma, b_sigma) << c.box << " ray " << k;
        EXPECT_NEAR(a0, b0, 1e-12 * (1 + b0)) << c.box << " ray " << k;
        EXPECT_NEAR(a1, b1, 1e-12 * (1 + b1)) << c.box << " ray " << k;
      }
    }
    EXPECT_GT(walked, 100) << c.box;
  }
}

// Negative control: where a node is a tile, a walk started below it splits the tile into its
// voxels, so the start level must stay above tiles (and the test above can tell levels apart).
TEST(MajorantTraversal, AWalkStartedBelowATileSplitsIt) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->tree().addTile(1, openvdb::Coord(8, 0, 0), 1.5f, true);  // the 8^3 voxels of a leaf, one value
  grid->tree().addTile(1, openvdb::Coord(16, 0, 0), 0.5f, true);
  const openvdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
  EXPECT_EQ(majorantWalkStartLevel(grid->tree(), active), 0) << "no leaf exists below the tiles";
  const openvdb::BBoxd box(active.min().asVec3d(), active.max().asVec3d() + openvdb::Vec3d(1.0));
  MajorantRay ray(openvdb::Vec3d(0, 0.5, 0.5), openvdb::Vec3d(1, 0, 0), 0.0, 1e3);
  ASSERT_TRUE(ray.clip(box));
  const std::vector<Segment> tiles{{8, 16, 1.5}, {16, 24, 0.5}};
  EXPECT_EQ(segments(ray, *grid, 0), tiles);
  EXPECT_EQ(segments(ray, *grid, 2), tiles);
  EXPECT_EQ(segments(ray, *grid, -1).size(), 16u);
}

}  // namespace
}  // namespace vdbappear
