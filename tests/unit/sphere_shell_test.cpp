// Shell mapping over a sphere (surface/sphere_shell.h): the tangent frame, the inverse mapping, and
// the mesh of a flat map, which is the sphere.
#include "libvdbappear/math/constants.h"
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
