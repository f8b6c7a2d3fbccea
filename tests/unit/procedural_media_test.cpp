// The procedural media of vdb_make_medium: accepted by the reader, deterministic, S SPD everywhere,
// fibers aligned with their yarns or strands, and the statistics their parameters imply.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/procedural/cloud_medium.h"
#include "libvdbappear/procedural/exemplar_medium.h"
#include "libvdbappear/procedural/hairy_ball_medium.h"
#include "libvdbappear/procedural/shape_medium.h"
#include "libvdbappear/procedural/velvet_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <functional>
#include <map>

namespace vdbappear {
namespace {

using Maker = std::function<MediumPtr(std::uint64_t seed)>;

// Every kind at a small resolution.
const std::map<std::string, Maker>& smallKinds() {
  static const std::map<std::string, Maker> kinds{
      {"twill", [](std::uint64_t seed) { WeaveParams p; p.resolution = 48; p.seed = seed; return makeWeave(p); }},
      {"satin", [](std::uint64_t seed) {
         WeaveParams p; p.pattern = "satin"; p.yarns = 5; p.resolution = 40; p.seed = seed; return makeWeave(p); }},
      {"velvet", [](std::uint64_t seed) { VelvetParams p; p.resolution = 48; p.yarns = 2; p.seed = seed; return makeVelvet(p); }},
      {"hairy-ball", [](std::uint64_t seed) { HairyBallParams p; p.resolution = 48; p.seed = seed; return makeHairyBall(p); }},
      {"sphere-sggx", [](std::uint64_t seed) {
         ShapeParams p; p.shape = Shape::Sphere; p.resolution = 24; p.seed = seed; p.variation = 0.5;
         p.phase = PhaseChoice::SggxFiber; p.axis = Vec3(1, 2, 3); return makeShape(p); }},
      {"cloud", [](std::uint64_t seed) { CloudParams p; p.resolution = 32; p.seed = seed; return makeCloud(p); }},
      {"exemplars", [](std::uint64_t seed) { ExemplarParams p; p.resolution = 24; p.count = 3; p.seed = seed; return makeExemplars(p); }},
  };
  return kinds;
}

class EveryKind : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryKind, IsAcceptedByTheReaderAfterARoundTrip) {
  const MediumPtr medium = smallKinds().at(GetParam())(1);
  test::TempDir dir;
  const std::string path = dir.path("m.vdb");
  writeMedium(*medium, path, "test");
  const MediumPtr back = readMedium(path);
  EXPECT_GT(back->density->activeVoxelCount(), 0u);
  EXPECT_TRUE(test::gridsMatch(*medium->density, *back->density, 0));
}

TEST_P(EveryKind, SameSeedSameMediumWhateverTheThreadCount) {
  const Maker& make = smallKinds().at(GetParam());
  const MediumPtr a = make(3);
  MediumPtr b;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    b = make(3);
  }
  EXPECT_TRUE(test::gridsMatch(*a->density, *b->density, 0));
  EXPECT_TRUE(test::gridsMatch(*a->albedo, *b->albedo, 0));
  if (a->sggx_diag) EXPECT_TRUE(test::gridsMatch(*a->sggx_diag, *b->sggx_diag, 0));
  if (a->sggx_offdiag) EXPECT_TRUE(test::gridsMatch(*a->sggx_offdiag, *b->sggx_offdiag, 0));
}

TEST_P(EveryKind, AnotherSeedChangesTheMedium) {
  const Maker& make = smallKinds().at(GetParam());
  const MediumPtr a = make(3), b = make(4);
  const bool same = test::gridsMatch(*a->density, *b->density, 0) && test::gridsMatch(*a->albedo, *b->albedo, 0);
  EXPECT_FALSE(same);
}

TEST_P(EveryKind, SggxMatricesArePositiveDefiniteEverywhere) {
  const MediumPtr medium = smallKinds().at(GetParam())(1);
  if (!medium->sggx_diag) GTEST_SKIP() << "no SGGX grids";
  auto offdiag = medium->sggx_offdiag->getConstAccessor();
  std::size_t checked = 0;
  for (auto d = medium->sggx_diag->cbeginValueOn(); d; ++d, ++checked) {
    const openvdb::Vec3s o = offdiag.getValue(d.getCoord());
    ASSERT_TRUE(isPositiveDefinite(Vec3((*d)[0], (*d)[1], (*d)[2]), Vec3(o[0], o[1], o[2])))
        << GetParam() << " at " << d.getCoord();
  }
  EXPECT_EQ(checked, medium->density->activeVoxelCount());
}

INSTANTIATE_TEST_SUITE_P(Procedural, EveryKind,
                         ::testing::Values("twill", "satin", "velvet", "hairy-ball", "sphere-sggx", "cloud", "exemplars"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// --- helpers over active voxels ---

Mat3 sggxAt(const Medium& m, const openvdb::Coord& c) {
  const openvdb::Vec3s d = m.sggx_diag->getConstAccessor().getValue(c);
  const openvdb::Vec3s o = m.sggx_offdiag->getConstAccessor().getValue(c);
  return sggxMatrix(Vec3(d[0], d[1], d[2]), Vec3(o[0], o[1], o[2]));
}

// Unit eigenvector of the smallest eigenvalue of S: the fiber direction of a fiber-like SGGX.
Vec3 fiberDirection(const Mat3& S) {
  Eigen::SelfAdjointEigenSolver<Mat3> eigen(S);
  return eigen.eigenvectors().col(0);
}

double angleDegrees(const Vec3& a, const Vec3& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / kPi;
}

double totalMass(const Medium& m) {
  const double voxel_volume = std::pow(m.transform().voxelSize()[0], 3);
  double sum = 0;
  for (auto v = m.density->cbeginValueOn(); v; ++v) sum += *v;
  return sum * voxel_volume;
}

Vec3 worldOf(const Medium& m, const openvdb::Coord& c) {
  const openvdb::Vec3d w = m.transform().indexToWorld(c);
  return Vec3(w[0], w[1], w[2]);
}

// --- twill ---

// For the twill, the eigenvector of S with the smallest eigenvalue follows the yarn: warp voxels
// (pink: green channel < 0.5) along x, weft voxels along y. A fiber leaves its yarn's axis by the
// twist angle, at most atan(2 pi / pitch * |(0.42, 0.14)|) = 34.8 degrees at the yarn's edge, and
// the axis leaves the fabric plane by the crimp, at most atan(2 * 0.16 * pi / 2) = 26.7 degrees
// where the yarn dives between crossings: 61.5 in all.
TEST(Twill, FibersFollowTheirYarns) {
  WeaveParams p;
  p.resolution = 96;
  const MediumPtr m = makeWeave(p);
  auto albedo = m->albedo->getConstAccessor();
  std::vector<double> angles;
  for (auto v = m->density->cbeginValueOn(); v; ++v) {
    const bool warp = albedo.getValue(v.getCoord())[1] < 0.5;
    const Mat3 S = sggxAt(*m, v.getCoord());
    const Vec3 yarn = warp ? Vec3::UnitX() : Vec3::UnitY();
    angles.push_back(angleDegrees(fiberDirection(S), yarn));
    Eigen::SelfAdjointEigenSolver<Mat3> eigen(S);
    ASSERT_NEAR(eigen.eigenvalues()[0], p.roughness * p.roughness, 1e-5);
    ASSERT_NEAR(eigen.eigenvalues()[1], 1, 1e-5);
  }
  std::sort(angles.begin(), angles.end());
  EXPECT_LE(angles.back(), 61.5);
  EXPECT_LE(angles[angles.size() / 2], 20.0) << "median angle";
}

// Mass = fiber density * fiber coverage (pi (r/s)^2, exact: fibers never leave their cells) *
// yarn volume (2 sets * yarns * yarns long * pi a b, exact: vertical sections of the crimped yarn
// are the ellipse). Warp and weft overlap a little near crossings, where a point counts once.
TEST(Twill, MassMatchesFiberCoverageOfTheYarns) {
  for (const std::string pattern : {"plain", "twill", "satin"}) {
    WeaveParams p;
    p.pattern = pattern;
    p.yarns = pattern == "satin" ? 5 : 4;
    p.resolution = 160;
    const double yarn_volume = 2.0 * p.yarns * p.yarns * kPi * WeaveGeometry::kHalfWidth * WeaveGeometry::kHalfHeight;
    const double expected = p.fiber_density * WeaveGeometry::kFiberCoverage * yarn_volume;
    EXPECT_NEAR(totalMass(*makeWeave(p)) / expected, 1.0, 0.03) << pattern;
  }
}

TEST(Twill, WarpShowsOnTopWhereThePatternSaysSo) {
  // Looking down on a 2/2 twill at each crossing centre, the topmost voxel is warp where warpOver.
  WeaveParams p;
  p.resolution = 64;
  const MediumPtr m = makeWeave(p);
  const WeavePattern pattern = WeavePattern::byName("twill");
  const double h = m->transform().voxelSize()[0];
  auto density = m->density->getConstAccessor();
  auto albedo = m->albedo->getConstAccessor();
  for (int i = 0; i < p.yarns; ++i)      // warp yarn i runs along x at y = i + 0.5
    for (int j = 0; j < p.yarns; ++j) {  // weft yarn j runs along y at x = j + 0.5
      const openvdb::Vec3d index = m->transform().worldToIndex(openvdb::Vec3d(j + 0.5, i + 0.5, 0));
      const int x = int(std::lround(index[0])), y = int(std::lround(index[1]));
      int z = int(1 / h);
      while (z >= 0 && density.getValue({x, y, z}) == 0) --z;
      ASSERT_GE(z, 0);
      const bool warp_on_top = albedo.getValue({x, y, z})[1] < 0.5;
      EXPECT_EQ(warp_on_top, pattern.warpOver(i, j)) << "crossing " << i << "," << j;
    }
}

// --- velvet ---

TEST(Velvet, PileIsUprightAndCoversItsShareOfTheArea) {
  VelvetParams p;
  p.resolution = 160;
  const MediumPtr m = makeVelvet(p);
  auto density = m->density->getConstAccessor();
  // A horizontal slice through the middle of the pile, away from the patch's edges: each fiber
  // cuts it in an ellipse of area pi r^2 / cos(theta), theta <= lean + tilt = 18 degrees, so the
  // fibers' areas add up to c / cos(theta) of the slice, c = pi (r / spacing)^2. Tilted fibers
  // cross, and a point inside two counts once: the covered share lies between that of
  // independently placed fibers, 1 - exp(-c), and c / cos(18 degrees).
  const double coverage = kPi * p.pile_radius * p.pile_radius / (p.pile_spacing * p.pile_spacing);
  double sum = 0;
  int count = 0;
  std::vector<double> angles;
  const double z = 1.0;
  for (auto v = m->density->cbeginValueOn(); v; ++v) {
    const Vec3 w = worldOf(*m, v.getCoord());
    if (w.z() > 0.85) angles.push_back(angleDegrees(fiberDirection(sggxAt(*m, v.getCoord())), Vec3::UnitZ()));
  }
  // The same holds at the patch's edges: fibers rooted beyond them (the pile repeats with the
  // patch's period) lean in, so the pile has no bald strip where it leans away.
  for (const auto& [x0, x1] : {std::pair{1.0, 3.0}, std::pair{0.02, 0.3}, std::pair{3.7, 3.98}}) {
    const openvdb::Vec3d lo = m->transform().worldToIndex({x0, 1, z}), hi = m->transform().worldToIndex({x1, 3, z});
    sum = 0;
    count = 0;
    for (int x = int(lo[0]); x <= int(hi[0]); ++x)
      for (int y = int(lo[1]); y <= int(hi[1]); ++y, ++count) sum += density.getValue({x, y, int(std::lround(lo[2]))});
    const double ratio = sum / count / (p.pile_density * coverage);
    EXPECT_GT(ratio, (1 - std::exp(-coverage)) / coverage - 0.02) << x0 << ".." << x1;
    EXPECT_LT(ratio, 1 / std::cos((p.lean_degrees + p.tilt_degrees) * kPi / 180) + 0.03) << x0 << ".." << x1;
  }
  std::sort(angles.begin(), angles.end());
  EXPECT_LE(angles.back(), p.lean_degrees + p.tilt_degrees + 0.5);
}

// --- hairy ball ---

TEST(HairyBall, StrandsAreRadialAndTheMassIsCorePlusStrands) {
  HairyBallParams p;
  p.resolution = 200;
  const MediumPtr m = makeHairyBall(p);
  std::vector<double> angles;
  for (auto v = m->density->cbeginValueOn(); v; ++v) {
    const Vec3 w = worldOf(*m, v.getCoord());
    if (w.norm() > p.radius + 0.05) angles.push_back(angleDegrees(fiberDirection(sggxAt(*m, v.getCoord())), w));
  }
  std::sort(angles.begin(), angles.end());
  EXPECT_LE(angles[angles.size() / 2], p.tilt_degrees);
  const double core = 4.0 / 3.0 * kPi * std::pow(p.radius, 3) * p.core_density;
  const double strands = hairyBallStrandCount(p) * kPi * p.strand_radius * p.strand_radius *
                         (p.hair_length - p.strand_radius) * p.strand_density;
  // Strands that lean toward each other cross near their roots, where a point counts once: the
  // mass falls short of the sum by a few percent (3.0% at these settings), never exceeds it.
  const double ratio = totalMass(*m) / (core + strands);
  EXPECT_GT(ratio, 0.95);
  EXPECT_LT(ratio, 1.005);
}

TEST(HairyBall, TwoMaterialsSplitTheFurByHemisphere) {
  HairyBallParams p;
  p.resolution = 64;
  p.two_materials = true;
  const MediumPtr m = makeHairyBall(p);
  auto albedo = m->albedo->getConstAccessor();
  for (auto v = m->density->cbeginValueOn(); v; ++v) {
    const Vec3 w = worldOf(*m, v.getCoord());
    if (std::abs(w.x()) < 0.3) continue;  // strands lean across the equator
    const openvdb::Vec3s a = albedo.getValue(v.getCoord());
    const Vec3 expected = w.x() > 0 ? p.material_a : p.material_b;
    ASSERT_NEAR(a[0], expected.x(), 1e-6) << v.getCoord();
  }
}

// --- shapes and cloud ---

TEST(Shapes, FillFractionAndMeanDensityAreExact) {
  ShapeParams p;
  p.resolution = 32;
  p.density = 7;
  p.variation = 0.6;  // mean 0 over whole periods: the mean density stays rho
  for (Shape shape : {Shape::Cube, Shape::Sphere, Shape::Slab}) {
    p.shape = shape;
    const MediumPtr m = makeShape(p);
    const double n = double(m->density->activeVoxelCount());
    double sum = 0;
    for (auto v = m->density->cbeginValueOn(); v; ++v) sum += *v;
    if (shape == Shape::Cube) {
      EXPECT_EQ(n, 32.0 * 32 * 32);
      EXPECT_NEAR(sum / n, p.density, 1e-4);
    } else if (shape == Shape::Sphere) {
      EXPECT_NEAR(n / (32.0 * 32 * 32), kPi / 6, 0.01);
    } else {
      EXPECT_EQ(n, 32.0 * 32 * 8);  // thickness 0.25 of size 1
    }
  }
}

TEST(Shapes, PhaseChoicesWriteTheContractsGrids) {
  ShapeParams p;
  p.resolution = 8;
  p.phase = PhaseChoice::Hg;
  p.g = 0.7;
  MediumPtr m = makeShape(p);
  EXPECT_FALSE(m->hasSggx());
  EXPECT_NEAR(*hgGMetadata(m->metadata), 0.7, 1e-6);
  p.phase = PhaseChoice::SggxSurface;
  p.axis = Vec3(0, 0, 1);
  p.roughness = 0.2;
  m = makeShape(p);
  const Mat3 S = sggxAt(*m, openvdb::Coord(3));
  EXPECT_NEAR(S(2, 2), 1, 1e-6);  // surface-like: normal eigenvalue 1, tangent ones roughness^2
  EXPECT_NEAR(S(0, 0), 0.04, 1e-6);
}

TEST(Cloud, CoversTheRequestedShareOfItsSphere) {
  for (double coverage : {0.3, 0.6}) {
    CloudParams p;
    p.resolution = 56;  // not the 48^3 lattice that sets the threshold
    p.coverage = coverage;
    const MediumPtr m = makeCloud(p);
    int sphere_voxels = 0;
    for (int x = 0; x < p.resolution; ++x)
      for (int y = 0; y < p.resolution; ++y)
        for (int z = 0; z < p.resolution; ++z) sphere_voxels += worldOf(*m, {x, y, z}).norm() <= 0.5 * p.size;
    EXPECT_NEAR(double(m->density->activeVoxelCount()) / sphere_voxels, coverage, 0.03);
    float max = 0;
    for (auto v = m->density->cbeginValueOn(); v; ++v) max = std::max(max, *v);
    EXPECT_LE(max, p.density);
    EXPECT_GT(max, 0.5 * p.density);
    EXPECT_NEAR(*hgGMetadata(m->metadata), p.g, 1e-6);
  }
}

// --- exemplars ---

TEST(Exemplars, BlocksAndLayoutFollowTheParameters) {
  ExemplarParams p;
  p.resolution = 64;
  p.count = 5;
  p.layout_width = 6;
  p.layout_height = 3;
  const MediumPtr m = makeExemplars(p);
  const openvdb::CoordBBox box = m->density->evalActiveVoxelBoundingBox();
  EXPECT_EQ(box.min().x(), 0);
  EXPECT_EQ(box.max().x(), p.count * p.resolution - 1);
  ASSERT_EQ(m->other_grids.size(), 1u);
  const auto layout = openvdb::gridPtrCast<openvdb::Int32Grid>(m->other_grids[0]);
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->getName(), grid_names::kExemplarLayout);
  EXPECT_EQ(layout->activeVoxelCount(), 18u);
  std::set<int> used;
  for (auto v = layout->cbeginValueOn(); v; ++v) {
    EXPECT_GE(*v, 0);
    EXPECT_LT(*v, p.count);
    used.insert(*v);
  }
  EXPECT_GT(used.size(), 2u);
  EXPECT_EQ(m->metadata.metaValue<int>(metadata_names::kExemplarCount), p.count);
  // Each block holds a whole woven tile: its mass is that of Twill.MassMatchesFiberCoverageOfTheYarns.
  std::vector<double> mass(std::size_t(p.count), 0.0);
  for (auto v = m->density->cbeginValueOn(); v; ++v) mass[std::size_t(v.getCoord().x() / p.resolution)] += *v;
  const double yarn_volume =
      2.0 * p.block_yarns * p.block_yarns * kPi * WeaveGeometry::kHalfWidth * WeaveGeometry::kHalfHeight;
  const double expected = p.fiber_density * WeaveGeometry::kFiberCoverage * yarn_volume;
  for (double block : mass) EXPECT_NEAR(block * std::pow(m->transform().voxelSize()[0], 3) / expected, 1.0, 0.03);
}

}  // namespace
}  // namespace vdbappear
