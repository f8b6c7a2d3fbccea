// Shell mapping over a mesh by its UVs (surface/mesh_shell.h): the subdivision, the map point of a
// hit (tile coordinates and tangent frame) against the displaced triangles and against SphereShell
// over a UV sphere, mirrored UVs, and what it refuses.
#include "libvdbappear/render/mesh_file.h"
#include "libvdbappear/surface/mesh_shell.h"
#include "libvdbappear/surface/sphere_shell.h"

#include "support/temp_dir.h"
#include "support/test_random.h"
#include "support/uv_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vdbappear {
namespace {

// The unit square z = 0 as two triangles, uv = (x, y) or, mirrored, (x, 1 - y).
std::vector<UvTriangle> square(bool mirrored = false) {
  const auto corner = [mirrored](double x, double y) { return std::make_pair(Vec3(x, y, 0), Point2(x, mirrored ? 1 - y : y)); };
  std::vector<UvTriangle> triangles;
  for (const auto& corners : {std::array{corner(0, 0), corner(1, 0), corner(1, 1)}, std::array{corner(0, 0), corner(1, 1), corner(0, 1)}}) {
    UvTriangle t;
    for (int k = 0; k < 3; ++k) {
      t.position[k] = corners[k].first;
      t.normal[k] = Vec3::UnitZ();
      t.uv[k] = corners[k].second;
    }
    triangles.push_back(t);
  }
  return triangles;
}

Vec3 pointOf(const Triangle& t, const Point2& b) { return (1 - b.x() - b.y()) * t[0] + b.x() * t[1] + b.y() * t[2]; }

// Over the square, tiled 2 x 3 times with a map of 4 x 4 cells: the diagonal spans hypot(8, 12)
// cells, so k = 15; every hit's tile coordinates are its position's (x, y) times the tiles, which
// checks the order of the sub-triangles against mapPoint's reading of it.
TEST(MeshShell, MapPointOfAHitIsWhereItsTriangleLies) {
  MeshShell shell(square(), 2, 3);
  const std::vector<Triangle> triangles = shell.displace(HeightField(4, 4, 0.25), 1);
  EXPECT_EQ(shell.subdivisions(), 15);
  ASSERT_EQ(triangles.size(), std::size_t(2 * 15 * 15));
  test::TestRandom random(3);
  double area = 0;
  for (std::uint32_t p = 0; p < triangles.size(); ++p) {
    const Triangle& t = triangles[p];
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    area += 0.5 * n.norm();
    EXPECT_GT(n.z(), 0) << p;  // as the base triangle
    const double b1 = random.uniform(), b2 = (1 - b1) * random.uniform();
    const Vec3 x = pointOf(t, Point2(b1, b2));
    const MeshShell::MapPoint at = shell.mapPoint(p, Point2(b1, b2));
    EXPECT_NEAR(at.tile.x(), 2 * x.x(), 1e-12) << p;
    EXPECT_NEAR(at.tile.y(), 3 * x.y(), 1e-12) << p;
    EXPECT_NEAR((at.frame.s - Vec3::UnitX()).norm(), 0, 1e-12);
    EXPECT_NEAR((at.frame.t - Vec3::UnitY()).norm(), 0, 1e-12);
  }
  EXPECT_NEAR(area, 1, 1e-12);
  EXPECT_NEAR(shell.meanTileWidth(), std::sqrt(1.0 / 6), 1e-12);
}

// Heights go along the shading normal, bilinear between the map's vertices, and repeat every tile.
TEST(MeshShell, DisplacesAlongTheNormalByTheMapsHeight) {
  HeightField ramp(2, 2, 0.5);
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i) ramp.at(i, j) = 0.1 * i + 0.01 * j;
  MeshShell shell(square(), 1, 1);
  const std::vector<Triangle> triangles = shell.displace(ramp, 2, 4);  // 4 vertices per cell: k = 12
  EXPECT_EQ(shell.subdivisions(), 12);
  for (const Triangle& t : triangles)
    for (const Vec3& p : t) {
      const double x = p.x() == 1 ? 0 : p.x(), y = p.y() == 1 ? 0 : p.y();  // the next tile begins there
      EXPECT_NEAR(p.z(), 2 * (0.2 * x + 0.02 * y), 1e-12) << p.transpose();
    }
}

// Over a UV sphere parameterised as SphereShell, a hit's tile coordinates and frame are the
// sphere's at that point, up to the facets: UVs are linear over a flat facet, longitudes and
// latitudes are not (measured: at most 0.0066 tiles, 0.11 of the map's 16 cells, within 72 degrees
// of the equator; 0.009 toward the poles, where a facet's rows differ most in width).
TEST(MeshShell, OverAUvSphereIsTheSphereShell) {
  const SphereShell sphere = SphereShell::ofTiles(Vec3(0.5, -1, 2), 0.8, 8, 4);
  MeshShell shell(test::uvSphere(sphere.centre, sphere.radius, 64, 32), 8, 4);
  const std::vector<Triangle> triangles = shell.displace(HeightField(16, 16, 0.05), 1);
  test::TestRandom random(4);
  int checked = 0;
  double largest = 0;
  for (int k = 0; k < 2000; ++k) {
    const auto p = std::uint32_t(random.uniform() * triangles.size());
    const double b1 = random.uniform(), b2 = (1 - b1) * random.uniform();
    const Vec3 x = pointOf(triangles[p], Point2(b1, b2));
    const Point2 expected = sphere.tileCoordinates(x);
    if (expected.y() < 0.4 || expected.y() > 3.6) continue;  // within 72 degrees of the equator
    ++checked;
    const MeshShell::MapPoint at = shell.mapPoint(p, Point2(b1, b2));
    largest = std::max({largest, std::abs(at.tile.x() - expected.x()), std::abs(at.tile.y() - expected.y())});
    const Frame f = sphere.frame(expected.x(), expected.y());
    EXPECT_GT(at.frame.n.dot(f.n), 1 - 2e-3);
    EXPECT_GT(at.frame.s.dot(f.s), 1 - 2e-3);
    EXPECT_GT(at.frame.t.dot(f.t), 1 - 2e-3);
    EXPECT_NEAR((at.frame.s.cross(at.frame.t) - at.frame.n).norm(), 0, 1e-12);
  }
  std::printf("largest difference in tile coordinates: %.4f tiles over %d points\n", largest, checked);
  EXPECT_GT(checked, 1500);
  EXPECT_LT(largest, 0.01);
}

// Mirrored UVs turn the map over: its y runs along -y of the square, and the frame follows it.
TEST(MeshShell, MirroredUvsTurnTheFrame) {
  MeshShell shell(square(true), 1, 1);
  const std::vector<Triangle> triangles = shell.displace(HeightField(2, 2, 0.5), 1);
  const MeshShell::MapPoint at = shell.mapPoint(0, Point2(0.2, 0.3));
  const Vec3 x = pointOf(triangles[0], Point2(0.2, 0.3));
  EXPECT_NEAR(at.tile.y(), 1 - x.y(), 1e-12);
  EXPECT_NEAR((at.frame.s - Vec3::UnitX()).norm(), 0, 1e-12);
  EXPECT_NEAR((at.frame.t + Vec3::UnitY()).norm(), 0, 1e-12);
  EXPECT_NEAR((at.frame.n - Vec3::UnitZ()).norm(), 0, 1e-12);
}

// tile_to_frame is the UV Jacobian in the hit's frame: over a flat, tilted triangle whose UVs are
// sheared and stretched (and, mirrored, turned over), the step between two points of a displaced
// triangle, in (s, t), is tile_to_frame times their step in tile coordinates, and lies in the plane.
// This is the M of the prefiltered model's TileStretch on a mesh (render/render_scene.h), where a
// transposed or inverted matrix would read S at wrong directions.
TEST(MeshShell, TileToFrameIsTheUvJacobian) {
  for (const bool mirrored : {false, true}) {
    UvTriangle base;
    base.position = {Vec3(0, 0, 0), Vec3(2, 0.5, 0.3), Vec3(0.4, 1.5, -0.2)};
    const Vec3 n = (base.position[1] - base.position[0]).cross(base.position[2] - base.position[0]).normalized();
    base.normal = {n, n, n};
    base.uv = {Point2(0.1, 0.2), Point2(0.9, 0.3), Point2(0.6, 0.8)};
    if (mirrored)
      for (Point2& uv : base.uv) uv.y() = 1 - uv.y();
    MeshShell shell({base}, 3, 2);
    const std::vector<Triangle> triangles = shell.displace(HeightField(4, 4, 0.25), 1);
    test::TestRandom random(7);
    for (int k = 0; k < 50; ++k) {
      const auto p = std::uint32_t(random.uniform() * triangles.size());
      const Point2 b(0.2 + 0.2 * random.uniform(), 0.1 + 0.2 * random.uniform()), c(0.1 + 0.3 * random.uniform(), 0.4 + 0.2 * random.uniform());
      const MeshShell::MapPoint at = shell.mapPoint(p, b), other = shell.mapPoint(p, c);
      const Vec3 step = pointOf(triangles[p], c) - pointOf(triangles[p], b);
      const Eigen::Vector2d in_frame(at.frame.s.dot(step), at.frame.t.dot(step));
      const Eigen::Vector2d predicted = at.tile_to_frame * Eigen::Vector2d(other.tile.x() - at.tile.x(), other.tile.y() - at.tile.y());
      EXPECT_NEAR((in_frame - predicted).norm(), 0, 1e-12 * step.norm()) << "mirrored " << mirrored << ", triangle " << p;
      EXPECT_NEAR(at.frame.n.dot(step), 0, 1e-12 * step.norm());
      EXPECT_GT(std::abs(at.tile_to_frame(0, 1)), 0.1);  // sheared: a diagonal M would not test the order
    }
  }
}

// A file's UVs are read as written; where it has no normals, smooth ones are made, across its UV
// seams too (vertices at one position share their normal, so the map opens no crack there).
TEST(MeshShell, ReadsUvsAndMakesSmoothNormalsWhereTheFileHasNone) {
  const test::TempDir dir;
  const std::vector<UvTriangle> sphere = test::uvSphere(Vec3(1, 2, 3), 0.5, 16, 8);
  test::writeObj(dir.path("with.obj"), sphere);
  test::writeObj(dir.path("without.obj"), sphere, true, false);
  for (const char* name : {"with.obj", "without.obj"}) {
    const std::vector<UvTriangle> read = readUvMesh(dir.path(name));
    EXPECT_EQ(read.size(), std::size_t(16 * 8 * 2 - 2 * 16)) << name;  // less the poles' degenerate halves
    std::vector<std::pair<Vec3, Vec3>> seen;  // position, normal
    for (const UvTriangle& t : read)
      for (int k = 0; k < 3; ++k) {
        for (const auto& [position, normal] : seen)
          if ((position - t.position[k]).norm() < 1e-6) EXPECT_LT((normal - t.normal[k]).norm(), 1e-6) << name;
        seen.emplace_back(t.position[k], t.normal[k]);
        const Vec3 radial = (t.position[k] - Vec3(1, 2, 3)).normalized();
        EXPECT_GT(t.normal[k].dot(radial), std::string(name) == "with.obj" ? 1 - 1e-9 : 0.97) << name;
        const double v = std::asin(std::clamp(radial.z(), -1.0, 1.0)) / kPi + 0.5;  // latitude, 0 at the south pole
        EXPECT_NEAR(t.uv[k].y(), v, 1e-6) << name;
      }
  }
}

TEST(MeshShell, RefusesWhatItCannotPlace) {
  EXPECT_THROW(MeshShell({}, 1, 1), std::invalid_argument);
  EXPECT_THROW(MeshShell(square(), 0, 1), std::invalid_argument);
  std::vector<UvTriangle> bad = square();
  bad[1].uv[2].x() = std::numeric_limits<double>::quiet_NaN();
  try {
    MeshShell shell(bad, 1, 1);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "triangle 1 has a corner that is not finite");
  }
  MeshShell shell(square(), 64, 64);
  try {
    shell.displace(HeightField(64, 64, 1), 1, 1, 1000000);
    ADD_FAILURE() << "accepted";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("would be 67117698 triangles"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vdbappear
