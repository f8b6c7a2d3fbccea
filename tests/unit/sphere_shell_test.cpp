// Shell mapping over a sphere (surface/sphere_shell.h): the tangent frame, the inverse mapping, and
// the mesh of a flat map, which is the sphere.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/render/render_scene.h"
#include "libvdbappear/surface/sphere_shell.h"

#include "support/test_random.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace vdbappear {
namespace {

TEST(SphereShell, FrameIsRightHandedAndTangent) {
  const SphereShell shell = SphereShell::ofTiles(Vec3(1, 2, 3), 0.5, 8, 4);
  EXPECT_NEAR(shell.radius, 0.5 * 8 / (2 * kPi), 1e-15);
  test::TestRandom random(5);
  for (int k = 0; k < 100; ++k) {
    const double u = 8 * random.uniform(), v = 0.1 + 3.8 * random.uniform();  // away from the poles, where u is lost
    const Frame f = shell.frame(u, v);
    EXPECT_NEAR(f.s.norm(), 1, 1e-12);
    EXPECT_NEAR(f.t.norm(), 1, 1e-12);
    EXPECT_NEAR(f.s.dot(f.t), 0, 1e-12);
    EXPECT_NEAR((f.s.cross(f.t) - f.n).norm(), 0, 1e-12);
    EXPECT_NEAR((f.n - shell.normal(u, v)).norm(), 0, 1e-12);
    // s and t point along increasing u and v.
    const double h = 1e-6;
    EXPECT_GT((shell.point(u + h, v, 0) - shell.point(u, v, 0)).dot(f.s), 0);
    EXPECT_GT((shell.point(u, v + h, 0) - shell.point(u, v, 0)).dot(f.t), 0);
    // The tile coordinates of any point above or below (u, v) are (u, v).
    const Point2 uv = shell.tileCoordinates(shell.point(u, v, 0.3 * random.uniform() - 0.1));
    EXPECT_NEAR(uv.x(), u, 1e-9);
    EXPECT_NEAR(uv.y(), v, 1e-9);
  }
}

// The renderer's placement agrees with itself: a step along the base frame's x (y) at a point moves
// its map position along x (y) alone, on the sphere as on the plane, so f_low's directions and the
// texture lookups use the same axes (a swapped or mirrored frame fails this).
TEST(SphereShell, PlacementFrameFollowsTheMapPosition) {
  PrefilteredPlacement plane;
  plane.origin = Vec3(0.3, -0.2, 0.5);
  plane.size = 0.7;
  PrefilteredPlacement sphere = plane;
  sphere.shell = SphereShell::ofTiles(Vec3(1, 0, -1), 0.7, 8, 4);
  test::TestRandom random(9);
  for (const PrefilteredPlacement& placement : {plane, sphere}) {
    for (int k = 0; k < 50; ++k) {
      const Vec3 p = placement.shell ? placement.shell->point(8 * random.uniform(), 0.3 + 3.4 * random.uniform(), 0.01)
                                     : Vec3(random.uniform(), random.uniform(), 0.5);
      const Frame f = placement.mapPoint(p).frame;
      const double h = 1e-6;
      const Point2 at = placement.mapPoint(p).position, along_x = placement.mapPoint(p + h * f.s).position,
                   along_y = placement.mapPoint(p + h * f.t).position;
      if (along_x.x() < at.x() - 0.5 || along_y.y() < at.y() - 0.5) continue;  // stepped across a tile's edge
      EXPECT_GT(along_x.x() - at.x(), 0.5 * h / placement.size) << k;
      EXPECT_NEAR(along_x.y(), at.y(), 1e-3 * h / placement.size) << k;
      EXPECT_GT(along_y.y() - at.y(), 0.5 * h / placement.size) << k;
      EXPECT_NEAR(along_y.x(), at.x(), 1e-3 * h / placement.size) << k;
    }
  }
}

// A turn by a tiles takes each point above tile (0, b) to the point above tile (a, b), and its frame
// to that one's: the tiles of a latitude band are copies of one (render/surface_scene.h).
TEST(SphereShell, TurnTakesATileToTheTileEastOfIt) {
  const SphereShell shell = SphereShell::ofTiles(Vec3(0.3, -1, 2), 0.7, 6, 3);
  for (int a = 0; a < shell.tiles_x; ++a) {
    const RigidMotion turn = shell.turn(a);
    EXPECT_NEAR(turn.rotation.determinant(), 1, 1e-12);
    EXPECT_LT((turn.rotation * turn.rotation.transpose() - Mat3::Identity()).norm(), 1e-12);
    for (const double u : {0.0, 0.37, 1.0})
      for (const double v : {0.0, 0.61, 1.9, 3.0}) {
        EXPECT_LT((turn(shell.point(u, v, 0.05)) - shell.point(u + a, v, 0.05)).norm(), 1e-12) << a << " " << u << " " << v;
        if (v == 0.0 || v == 3.0) continue;  // the frame's east is a limit at the poles
        const Frame from = shell.frame(u, v), to = shell.frame(u + a, v);
        EXPECT_LT((turn.direction(from.s) - to.s).norm() + (turn.direction(from.n) - to.n).norm(), 1e-12) << a;
      }
  }
}

// A flat map's mesh lies on the sphere, faces outward, and covers 4 pi r^2 (less the facets' sag).
TEST(SphereShell, FlatMapMeshesTheSphere) {
  const SphereShell shell = SphereShell::ofTiles(Vec3(0, 0, 1), 1.0, 8, 4);
  const HeightField flat(16, 16, 1.0 / 16);
  const std::vector<Triangle> triangles = shellTriangles(flat, shell, 1);
  EXPECT_EQ(triangles.size(), std::size_t(2 * 16 * 16 * 8 * 4));
  double area = 0;
  for (const Triangle& t : triangles) {
    for (const Vec3& p : t) EXPECT_NEAR((p - shell.centre).norm(), shell.radius, 1e-12);
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    area += 0.5 * n.norm();
    if (n.norm() > 1e-12) EXPECT_GT(n.dot((t[0] + t[1] + t[2]) / 3 - shell.centre), 0);
  }
  const double sphere = 4 * kPi * shell.radius * shell.radius;
  EXPECT_NEAR(area, sphere, 0.005 * sphere);
  EXPECT_LT(area, sphere);
}

}  // namespace
}  // namespace vdbappear
