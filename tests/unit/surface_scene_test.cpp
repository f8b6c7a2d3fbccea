// A tiled height field as copies of one tile (SurfaceScene's Embree instances) hits as its tiles
// laid out as triangles do: the same distances, normals and surfaces, up to some ten float roundings
// from the seams between tiles. Exactly on a seam a ray can pass between two copies (each ray is
// rounded into each copy's frame, and the shared edge belongs to one copy); the flattened tiles
// share their vertices bit for bit and do not leak there. The same for a sphere's tiles as turns of
// one tile per latitude band, whose normals turn with their copies.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/height_field_mesh.h"
#include "libvdbappear/surface/sphere_shell.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace vdbappear {
namespace {

// 16 x 16 cells whose opposite edges match, so that its tiles join without gaps.
HeightField periodicBumps() {
  HeightField field(16, 16, 0.05);
  for (int j = 0; j <= 16; ++j)
    for (int i = 0; i <= 16; ++i)
      field.at(i, j) = 0.04 * std::sin(2 * kPi * i / 16) * std::cos(4 * kPi * j / 16) + 0.01 * std::cos(2 * kPi * (i + j) / 8);
  return field;
}

TEST(SurfaceScene, CopiesHitAsTheTilesTheyStandFor) {
  const HeightField field = periodicBumps();
  HeightFieldPlacement placement;
  placement.origin = Vec3(-0.3, 0.2, 0.1);
  placement.tiles_x = 3;
  placement.tiles_y = 2;
  SurfaceScene flat, copied;
  flat.addGlossy(heightFieldTriangles(field, placement), 2);
  std::vector<RigidMotion> copies;
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 3; ++a) copies.push_back(RigidMotion::translation(Vec3(a, b, 0) * 0.8));  // 16 cells of 0.05
  HeightFieldPlacement one = placement;
  one.tiles_x = one.tiles_y = 1;
  copied.addGlossy(heightFieldTriangles(field, one), 2, {}, copies);
  flat.commit();
  copied.commit();

  const auto expectSameHit = [&](const Vec3& o, const Vec3& d) {
    const auto a = flat.intersect(o, d, 0, 100), b = copied.intersect(o, d, 0, 100);
    ASSERT_EQ(bool(a), bool(b)) << o.transpose() << " toward " << d.transpose();
    EXPECT_EQ(flat.occluded(o, d, 0, 100), copied.occluded(o, d, 0, 100)) << o.transpose();
    if (!a) return;
    EXPECT_NEAR(a->t, b->t, 1e-5) << o.transpose() << " toward " << d.transpose();
    EXPECT_LT((a->normal - b->normal).norm(), 1e-6) << o.transpose();
    EXPECT_EQ(b->brdf, 2);
  };
  // Straight down inside every cell of the 3 x 2 tiles (off its edges and diagonal, where the hit
  // triangle is either), and 1e-6 (some ten float roundings) to either side of the seams. All hit.
  int hits = 0, rays = 0;
  const auto down = [&](double x, double y) {
    const Vec3 o = placement.origin + Vec3(x, y, 1);
    expectSameHit(o, Vec3(0, 0, -1));
    hits += bool(copied.intersect(o, Vec3(0, 0, -1), 0, 100));
    ++rays;
  };
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 48; ++i) down((i + 0.7) * 0.05, (j + 0.2) * 0.05);
  for (const double side : {-1e-6, 1e-6})
    for (int k = 0; k < 40; ++k) {
      down(0.8 + side, (k + 0.35) * 0.04);  // the seams between columns of tiles
      down(1.6 + side, (k + 0.35) * 0.04);
      down((k + 0.35) * 0.06, 0.8 + side);  // and between rows
    }
  EXPECT_EQ(hits, rays);
  // Oblique rays from above, many grazing and crossing seams.
  RandomStream random(3, {0});
  for (int k = 0; k < 3000; ++k) {
    const Point2 u = random.uniform2(), v = random.uniform2();
    const Vec3 target = placement.origin + Vec3(2.4 * u.x(), 1.6 * u.y(), 0);
    const double cos_theta = 0.05 + 0.95 * v.x(), phi = 2 * kPi * v.y();
    const double sin_theta = std::sqrt(1 - cos_theta * cos_theta);
    const Vec3 d(sin_theta * std::cos(phi), sin_theta * std::sin(phi), -cos_theta);
    expectSameHit(target - 2 * d, d);
  }
}

TEST(SurfaceScene, TurnedCopiesHitAsTheSphereTilesTheyStandFor) {
  const HeightField field = periodicBumps();  // a tile 0.8 wide, bumps up to 0.05 high
  const SphereShell shell = SphereShell::ofTiles(Vec3(0.2, -0.1, 0.3), 0.8, 8, 4);
  SurfaceScene flat, turned;
  flat.addGlossy(shellTriangles(field, shell, 1), 2);
  std::vector<RigidMotion> turns;
  for (int a = 0; a < shell.tiles_x; ++a) turns.push_back(shell.turn(a));
  for (int b = 0; b < shell.tiles_y; ++b) turned.addGlossy(shellTileTriangles(field, shell, 1, 0, b), 2, {}, turns);
  flat.commit();
  turned.commit();

  // Toward points all over the sphere (poles and seams between tiles included) from outside it, at
  // angles from the normal there up to grazing; some pass on to the far side.
  RandomStream random(5, {0});
  int hits = 0, turned_normals = 0;
  for (int k = 0; k < 4000; ++k) {
    const Point2 at = random.uniform2(), v = random.uniform2();
    const Point2 uv(shell.tiles_x * at.x(), shell.tiles_y * at.y());
    const Frame frame = shell.frame(uv.x(), uv.y());
    const double cos_theta = 0.05 + 0.95 * v.x(), phi = 2 * kPi * v.y();
    const double sin_theta = std::sqrt(1 - cos_theta * cos_theta);
    const Vec3 d = -frame.toWorld(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
    const Vec3 o = shell.point(uv.x(), uv.y(), 0) - 3 * d;
    const auto a = flat.intersect(o, d, 0, 100), b = turned.intersect(o, d, 0, 100);
    ASSERT_EQ(bool(a), bool(b)) << o.transpose() << " toward " << d.transpose();
    EXPECT_EQ(flat.occluded(o, d, 0, 100), turned.occluded(o, d, 0, 100)) << o.transpose();
    if (!a) continue;
    ++hits;
    EXPECT_NEAR(a->t, b->t, 1e-5) << o.transpose() << " toward " << d.transpose();
    EXPECT_LT((a->normal - b->normal).norm(), 1e-6) << o.transpose() << " toward " << d.transpose();
    EXPECT_EQ(b->brdf, 2);
    turned_normals += std::floor(shell.tileCoordinates(o + b->t * d).x()) != 0;  // off the tiles as meshed
  }
  EXPECT_GT(hits, 3950);  // a grazing ray can pass over a dip below the base sphere
  EXPECT_GT(turned_normals, 3000);  // 7 in 8 hit a turned copy
}

}  // namespace
}  // namespace vdbappear
