// Level of detail for mipmaps of prefiltered maps (§4.7.2): the blend between two levels, a camera
// ray's pixel footprint on the base plane against the quad its pixel's corners cut out, the
// frequency of each level over paths, and surfaces that only their own level's paths see.
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/level_of_detail.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/mesh_shell.h"
#include "libvdbappear/surface/sphere_shell.h"

#include "support/uv_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {
namespace {

TEST(LevelOfDetail, BlendBracketsTheFootprintInLogFactor) {
  const std::vector<double> factors{1, 8, 32};
  const auto expect = [&](double cells, int lower, int upper, double weight) {
    const LevelBlend b = blendForFootprint(factors, cells);
    EXPECT_EQ(b.lower, lower) << cells;
    EXPECT_EQ(b.upper, upper) << cells;
    EXPECT_NEAR(b.weight, weight, 1e-12) << cells;
  };
  expect(0.3, 0, 0, 0);
  expect(1, 0, 0, 0);
  expect(std::sqrt(8.0), 0, 1, 0.5);  // half way between 1 and 8 in log
  expect(8, 1, 2, 0);
  expect(16, 1, 2, 0.5);
  expect(32, 2, 2, 0);
  expect(1e6, 2, 2, 0);
  const LevelBlend single = blendForFootprint({8}, 100);
  EXPECT_EQ(single.lower, 0);
  EXPECT_EQ(single.upper, 0);
}

// The footprint's area width is the square root of the area that the pixel's four corner rays cut
// out of the plane, for a camera looking down obliquely, in the middle and at a corner of the image.
TEST(LevelOfDetail, FootprintIsThePixelsAreaOnThePlane) {
  const int width = 400, height = 300;
  const PinholeCamera camera({Vec3(0.3, -3, 2), Vec3(0, 0, 0), Vec3(0, 0, 1), 40}, width, height);
  MipmapFootprint mipmap{Vec3(-50, -50, 0), 100, 100, 0.01, {1, 8}};
  const auto onPlane = [&](double x, double y) {
    const Ray r = camera.ray(x, y);
    return Vec3(r(-r.o.z() / r.d.z()));
  };
  for (const auto& [x, y] : {std::pair{200.5, 150.5}, std::pair{20.5, 280.5}, std::pair{390.5, 10.5}}) {
    const Vec3 a = onPlane(x - 0.5, y - 0.5), b = onPlane(x + 0.5, y - 0.5), c = onPlane(x + 0.5, y + 0.5),
               d = onPlane(x - 0.5, y + 0.5);
    const double area = 0.5 * std::abs((c - a).x() * (d - b).y() - (c - a).y() * (d - b).x());  // quad by its diagonals
    const std::optional<Footprint> f = footprintOn(mipmap, camera.ray(x, y));
    ASSERT_TRUE(f) << x << " " << y;
    EXPECT_NEAR(f->area_cells * mipmap.cell, std::sqrt(area), 2e-3 * std::sqrt(area)) << x << " " << y;
  }
  mipmap.width_x = 0.1;  // the tiles end before the ray meets the plane: no footprint
  EXPECT_FALSE(footprintOn(mipmap, camera.ray(20.5, 280.5)));
  EXPECT_FALSE(footprintOn(mipmap, Ray{Vec3(0, 0, 1), Vec3(0, 0, 1), 1e-3}));  // away from the plane
}

// The narrow width is the pixel's width across the view: for the pixel at the centre of a camera
// that looks down a plane's y axis, the mean length of the two edges its corner rays cut out across
// it, 1 / sqrt(17) (about a quarter) of the length they cut out along it (the view meets the plane 14
// degrees above it).
TEST(LevelOfDetail, NarrowFootprintIsThePixelsWidthAcrossTheView) {
  const int width = 400, height = 300;
  const PinholeCamera camera({Vec3(0, -4, 1), Vec3(0, 0, 0), Vec3(0, 0, 1), 40}, width, height);
  const MipmapFootprint mipmap{Vec3(-50, -50, 0), 100, 100, 0.01, {1, 8}};
  const auto onPlane = [&](double x, double y) {
    const Ray r = camera.ray(x, y);
    return Vec3(r(-r.o.z() / r.d.z()));
  };
  const Vec3 a = onPlane(199.5, 149.5), b = onPlane(200.5, 149.5), c = onPlane(200.5, 150.5), d = onPlane(199.5, 150.5);
  const double across = 0.5 * ((b - a).norm() + (c - d).norm()), along = 0.5 * ((d - a).norm() + (c - b).norm());
  const std::optional<Footprint> f = footprintOn(mipmap, camera.ray(200, 150));
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->narrow_cells * mipmap.cell, across, 2e-3 * across);
  EXPECT_NEAR(f->area_cells * mipmap.cell, std::sqrt(across * along), 2e-3 * std::sqrt(across * along));
  EXPECT_NEAR(along / across, std::sqrt(17.0), 0.01);  // 1 / cos theta: the ray's slope is 1 in 4
  EXPECT_EQ(f->cells(FootprintWidth::narrow), f->narrow_cells);
  EXPECT_EQ(f->cells(FootprintWidth::area), f->area_cells);
}

// Over a sphere (16 x 8 tiles of 32 x 32 cells on the unit sphere) a cell is 2 pi / 512 wide at the
// equator and sqrt(cos(latitude)) of that elsewhere, and the footprint widens as 1 / sqrt(cos) of the
// ray's angle to the normal, as on the plane; over a UV sphere mesh of the same parameterisation the
// same, up to its facets (128 x 64 quads).
TEST(LevelOfDetail, FootprintOnASphereAndAMesh) {
  const SphereShell sphere = SphereShell::ofTiles(Vec3(0, 0, 0.5), 2 * kPi / 16, 16, 8);
  MeshShell mesh(test::uvSphere(sphere.centre, sphere.radius, 128, 64), 16, 8);
  MipmapFootprint on_sphere, on_mesh;
  on_sphere.curved = sphereBase(sphere, 32, 32);
  on_mesh.curved = meshBase(mesh, 32, 32);
  const double equator_cell = 2 * kPi / 512, spread = 0.01;
  // Toward the equator, head on: t = 3.
  const Ray head_on{Vec3(0, -4, 0.5), Vec3(0, 1, 0), spread};
  for (const MipmapFootprint* m : {&on_sphere, &on_mesh}) {
    const std::optional<Footprint> f = footprintOn(*m, head_on);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->t, 3, 1e-3);
    EXPECT_NEAR(f->area_cells, 3 * spread / equator_cell, 0.01 * 3 * spread / equator_cell);
    EXPECT_NEAR(f->narrow_cells, f->area_cells, 1e-3 * f->area_cells);
  }
  // Toward latitude 60 degrees, 30 degrees off its normal.
  const double latitude = kPi / 3;
  const Vec3 n(0, -std::cos(latitude), std::sin(latitude)), point = sphere.centre + n;
  const Vec3 d = -(std::cos(kPi / 6) * n + std::sin(kPi / 6) * Vec3(1, 0, 0));
  const Ray oblique{point - 2 * d, d, spread};
  const double expected = 2 * spread / std::sqrt(std::cos(kPi / 6)) / (equator_cell * std::sqrt(std::cos(latitude)));
  for (const MipmapFootprint* m : {&on_sphere, &on_mesh}) {
    const std::optional<Footprint> f = footprintOn(*m, oblique);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->t, 2, 2e-3);
    EXPECT_NEAR(f->area_cells, expected, 0.02 * expected) << (m == &on_mesh ? "mesh" : "sphere");
    const double across = expected * std::sqrt(std::cos(kPi / 6));
    EXPECT_NEAR(f->narrow_cells, across, 0.02 * across) << (m == &on_mesh ? "mesh" : "sphere");
  }
  const Ray away{Vec3(0, -4, 0.5), Vec3(0, -1, 0), spread};
  EXPECT_FALSE(footprintOn(on_sphere, away));
  EXPECT_FALSE(footprintOn(on_mesh, away));
}

// Over many camera rays of one footprint half way between two levels, the coarser is chosen half
// the time; where no blend is needed no random number is drawn, and rays without spread get level 0.
TEST(LevelOfDetail, PathLevelsFollowTheBlendWeight) {
  const std::vector<MipmapFootprint> mipmaps{{Vec3(-1, -1, 0), 2, 2, 0.01, {1, 4, 16}}};
  const Ray down{Vec3(0, 0, 1), Vec3(0, 0, -1), 0.08};  // 8 cells: half way between 4 and 16
  RandomStream rng(7, {0});
  const int n = 20000;
  int coarser = 0;
  for (int i = 0; i < n; ++i) {
    const int level = pathLevel(mipmaps, down, rng);
    ASSERT_TRUE(level == 1 || level == 2) << level;
    coarser += level == 2;
  }
  EXPECT_NEAR(double(coarser) / n, 0.5, 4 * std::sqrt(0.25 / n));

  RandomStream a(3, {1}), b(3, {1});
  EXPECT_EQ(pathLevel(mipmaps, {Vec3(0, 0, 1), Vec3(0, 0, -1), 0.005}, a), 0);  // half a cell
  EXPECT_EQ(pathLevel(mipmaps, {Vec3(0, 0, 1), Vec3(0, 0, -1), 1.0}, a), 2);    // 100 cells
  EXPECT_EQ(pathLevel(mipmaps, {Vec3(5, 5, 1), Vec3(0, 0, -1), 0.08}, a), 2);   // misses the map: the coarsest
  EXPECT_EQ(pathLevel(mipmaps, {Vec3(0, 0, 1), Vec3(0, 0, -1), 0.0}, a), 0);    // not a camera ray
  EXPECT_EQ(a.uniform(), b.uniform());
}

// Toward the horizon the narrow width keeps the finer level that the area width leaves: a ray at
// cos theta = 1/400 whose footprint is 0.9 cells across (the original alone) is 18 cells by its area
// (the coarsest level alone).
TEST(LevelOfDetail, NarrowFootprintKeepsFinerLevelsTowardTheHorizon) {
  std::vector<MipmapFootprint> mipmaps{{Vec3(-10, -10, 0), 20, 20, 0.01, {1, 4, 16}}};
  const Vec3 d(std::sqrt(1 - 1.0 / 160000), 0, -1.0 / 400);
  const Ray grazing{Vec3(0, 0, 0) - 2 * d, d, 0.0045};  // t = 2: 0.009 across
  const std::optional<Footprint> f = footprintOn(mipmaps[0], grazing);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->narrow_cells, 0.9, 1e-9);
  EXPECT_NEAR(f->area_cells, 18, 1e-9);
  RandomStream a(3, {1}), b(3, {1});
  EXPECT_EQ(pathLevel(mipmaps, grazing, a), 0);
  mipmaps[0].levels_by = FootprintWidth::area;
  EXPECT_EQ(pathLevel(mipmaps, grazing, a), 2);
  EXPECT_EQ(a.uniform(), b.uniform());  // neither blends, so neither draws
}

std::vector<Triangle> square(double z) {
  const Vec3 p00(-1, -1, z), p10(1, -1, z), p11(1, 1, z), p01(-1, 1, z);
  return {{p00, p10, p11}, {p00, p11, p01}};
}

// A mipmap's level 0 and its last level (which also stands for every level above) are seen only by
// their own paths; a surface of no mipmap by every path.
TEST(SurfaceScene, EachLevelSeesItsOwnSurfaces) {
  SurfaceScene scene;
  scene.addDiffuse(square(-1), Rgb::Constant(0.5));
  scene.addGlossy(square(0), 0, DetailLevels{0, 0});
  scene.addPrefiltered(square(1), 0, DetailLevels{1, DetailLevels::kLastLevel});
  scene.commit();
  EXPECT_EQ(scene.levelCount(), 2);
  const Vec3 above(0.1, 0.2, 5), down(0, 0, -1);
  const auto level0 = scene.intersect(above, down, 0, 100, 0);
  ASSERT_TRUE(level0);
  EXPECT_NEAR(level0->t, 5, 1e-6);
  EXPECT_EQ(level0->brdf, 0);
  EXPECT_EQ(level0->prefiltered, -1);
  for (const int level : {1, 4}) {
    const auto hit = scene.intersect(above, down, 0, 100, level);
    ASSERT_TRUE(hit) << level;
    EXPECT_NEAR(hit->t, 4, 1e-6) << level;
    EXPECT_EQ(hit->prefiltered, 0) << level;
  }
  const Vec3 below(0.1, 0.2, -3), up(0, 0, 1);
  for (const int level : {0, 1}) EXPECT_NEAR(scene.intersect(below, up, 0, 100, level)->t, 2, 1e-6) << level;
  EXPECT_FALSE(scene.occluded(Vec3(0, 0, 0.5), up, 0, 2, 0));
  EXPECT_TRUE(scene.occluded(Vec3(0, 0, 0.5), up, 0, 2, 1));
  EXPECT_TRUE(scene.occluded(Vec3(0, 0, -0.5), down, 0, 2, 0));
  EXPECT_FALSE(scene.occluded(Vec3(0, 0, -0.5), Vec3(1, 0, 0), 0, 2, 0));
}

TEST(SurfaceScene, CommitsOnceBetweenAddsAndQueries) {
  SurfaceScene scene;
  scene.addDiffuse(square(0), Rgb::Constant(0.5));
  EXPECT_THROW(scene.intersect(Vec3(0, 0, 1), Vec3(0, 0, -1), 0, 10), std::logic_error);
  scene.commit();
  EXPECT_THROW(scene.addDiffuse(square(1), Rgb::Constant(0.5)), std::logic_error);
  EXPECT_THROW(scene.commit(), std::logic_error);
}

TEST(SurfaceScene, WithoutMipmapsOneLevelServesAll) {
  SurfaceScene scene;
  scene.addDiffuse(square(0), Rgb::Constant(0.5));
  scene.commit();
  EXPECT_EQ(scene.levelCount(), 1);
  for (const int level : {0, 3}) EXPECT_TRUE(scene.intersect(Vec3(0, 0, 1), Vec3(0, 0, -1), 0, 10, level)) << level;
}

}  // namespace
}  // namespace vdbappear
