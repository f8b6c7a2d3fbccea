// A micro-geometry over a periodic tile (surface/tile_edges.h; docs/displacement.md §6, "Tables over
// a periodic tile"): rays that leave the tile come back across the opposite edge, so that what a
// ray meets does not depend on where the tile's edges fall; the map alone (open edges) is the
// negative control. Also the check that a map tiles seamlessly.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/util/error.h"

#include "support/height_fields.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace vdbappear {
namespace {

constexpr int kCells = 32;
constexpr double kCell = 1.0 / kCells;

// A flat map with a ridge along its vertices of column `column` (or row, along_y), `height` high.
HeightField ridgeMap(int column, double height, bool along_y = false) {
  HeightField field(kCells, kCells, kCell);
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) field.at(i, j) = (along_y ? j : i) == column ? height : 0;
  return field;
}

// The map moved by (di, dj) cells, wrapping: vertex (i, j) holds the map's (i + di, j + dj).
HeightField rolled(const HeightField& map, int di, int dj) {
  HeightField out(map.cellsX(), map.cellsY(), map.cellSize());
  for (int j = 0; j <= map.cellsY(); ++j)
    for (int i = 0; i <= map.cellsX(); ++i) out.at(i, j) = map.at((i + di) % map.cellsX(), (j + dj) % map.cellsY());
  return out;
}

struct Layout {
  TileStretch stretch;
  double curvature;
};

// From near the tile's far edge toward +x (or +y), low enough to meet a ridge two cells past the
// near edge: over the periodic tile it meets the ridge, at the ridge's base position; alone, the
// ray escapes. On a plane, over a curved base and on a stretched tile.
TEST(PeriodicMicroGeometry, RayLeavingTheTileMeetsWhatLiesAcrossTheOppositeEdge) {
  const double height = 3 * kCell;
  for (const Layout& layout : {Layout{{}, 0.0}, Layout{{}, 0.2}, Layout{TileStretch::diagonal(0.6, 1.3), 0.0}})
    for (bool along_y : {false, true}) {
      const HeightField map = ridgeMap(2, height, along_y);
      const MicroGeometry open(map, layout.stretch, layout.curvature, TileEdges::Open);
      const MicroGeometry tiled(map, layout.stretch, layout.curvature, TileEdges::Periodic);
      const Point2 start = along_y ? Point2(16.5, 28.5) : Point2(28.5, 16.5);
      const MicroGeometry::Point p = tiled.at(start.x(), start.y());
      // 5.5 cells to the ridge's foot (the stretched tile's cells along the ray): aim at half its height.
      const double run = 5.5 * kCell * (along_y ? layout.stretch.matrix()(1, 1) : layout.stretch.matrix()(0, 0));
      const Vec3 w = (along_y ? Vec3(0, run, 0.5 * height) : Vec3(run, 0, 0.5 * height)).normalized();
      SCOPED_TRACE(testing::Message() << "curvature " << layout.curvature << ", stretched " << !layout.stretch.isIdentity()
                                      << ", along y " << along_y);
      EXPECT_TRUE(open.unoccluded(p, w));
      EXPECT_FALSE(open.trace(p, w));
      EXPECT_FALSE(tiled.unoccluded(p, w));
      const auto hit = tiled.trace(p, w);
      ASSERT_TRUE(hit);
      const double across = along_y ? hit->base.y() : hit->base.x(), along = along_y ? hit->base.x() : hit->base.y();
      EXPECT_GT(across, 1.0);  // on the ridge's near slope, in the tile
      EXPECT_LE(across, 2.0);
      EXPECT_NEAR(along, 16.5, 1e-9);
      // Aimed above the ridge's top with room to spare, it clears it (and every tile after it).
      const Vec3 high = (along_y ? Vec3(0, run, 3 * height) : Vec3(run, 0, 3 * height)).normalized();
      EXPECT_TRUE(tiled.unoccluded(p, high));
      EXPECT_FALSE(tiled.trace(p, high));
    }
}

// Rolling a periodic map by whole cells moves the tile's edges and nothing else: a ray from the
// same surface point meets the same point (moved by the roll) or nothing, over the periodic tile,
// for directions down to a degree above the horizon. The map alone disagrees (its edges moved).
TEST(PeriodicMicroGeometry, WhereTheTileEdgesFallDoesNotChangeWhatRaysMeet) {
  const HeightField map = test::periodicHeightField(kCells, kCell, {23.0, 11.0, 6.0, 3.0}, 0.012, 5);
  const int di = 13, dj = 21;
  const HeightField moved = rolled(map, di, dj);
  for (const Layout& layout : {Layout{{}, 0.0}, Layout{{}, 0.3}, Layout{TileStretch::diagonal(0.5, 1.0), 0.0}}) {
    SCOPED_TRACE(testing::Message() << "curvature " << layout.curvature << ", stretched " << !layout.stretch.isIdentity());
    const auto disagreements = [&](TileEdges edges) {
      const MicroGeometry a(map, layout.stretch, layout.curvature, edges), b(moved, layout.stretch, layout.curvature, edges);
      test::TestRandom random(7);
      int differ = 0, hits = 0;
      constexpr int kRays = 3000;
      for (int k = 0; k < kRays; ++k) {
        const double u = kCells * random.uniform(), v = kCells * random.uniform();
        const double elevation = (1 + 29 * random.uniform()) * kPi / 180, azimuth = 2 * kPi * random.uniform();
        const Vec3 w(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
        const MicroGeometry::Point p = a.at(u, v);
        const MicroGeometry::Point q = b.at(std::fmod(u - di + kCells, kCells), std::fmod(v - dj + kCells, kCells));
        const auto hit_a = a.trace(p, w), hit_b = b.trace(q, w);
        bool same = a.unoccluded(p, w) == b.unoccluded(q, w) && hit_a.has_value() == hit_b.has_value();
        if (same && hit_a) {
          ++hits;
          // The same point, its base moved by the roll (modulo the tile), to Embree's single precision
          // (a thousandth of a cell: points near a tile's far corner lie 0.8 away from the origin).
          const Point2 d = hit_a->base - hit_b->base - Point2(di, dj);
          const auto wrapped = [](double x) { return std::abs(x - kCells * std::round(x / kCells)); };
          same = wrapped(d.x()) < 1e-3 && wrapped(d.y()) < 1e-3;
        }
        differ += !same;
      }
      EXPECT_GT(hits, kRays / 4);  // grazing rays mostly meet a bump
      return double(differ) / kRays;
    };
    EXPECT_LE(disagreements(TileEdges::Periodic), 0.002);
    EXPECT_GE(disagreements(TileEdges::Open), 0.05);  // negative control
  }
}

// A ray that skims the tops of the tiles without rising is followed for a bounded distance: a
// horizontal ray above a flat map ends (escapes) instead of wrapping forever.
TEST(PeriodicMicroGeometry, HorizontalRayAboveTheTilesEnds) {
  const MicroGeometry tiled(ridgeMap(5, 0.0), {}, 0, TileEdges::Periodic);
  const MicroGeometry::Point p{Vec3(0.5, 0.5, 0.1), Vec3::UnitZ(), Point2(16, 16)};
  EXPECT_TRUE(tiled.unoccluded(p, Vec3(1, 0.3, 0).normalized()));
  EXPECT_FALSE(tiled.trace(p, Vec3(1, 0.3, 0).normalized()));
}

TEST(PeriodicMicroGeometry, SeamlessMapsPassAndOthersAreNamed) {
  EXPECT_NO_THROW(validateSeamless(test::periodicHeightField(kCells, kCell, {9.0, 4.0}, 0.01, 3), "tiles.exr"));
  EXPECT_NO_THROW(validateSeamless(HeightField(4, 4, 1), "flat.exr"));  // no relief, no step
  HeightField stepped = test::periodicHeightField(kCells, kCell, {9.0, 4.0}, 0.01, 3);
  stepped.at(kCells, 7) += 0.01;
  try {
    validateSeamless(stepped, "stepped.exr");
    ADD_FAILURE() << "a step along the seam passed";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("stepped.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(0, 7)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(validateSeamless(test::sinusoidHeightField(kCells, kCell, {9.0, 4.0}, 0.01, 3), "waves.exr"), MediumError);
}

}  // namespace
}  // namespace vdbappear
