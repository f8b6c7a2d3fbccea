// The compact form of a medium for rendering (medium/compact_attributes.h, medium/compact_medium.h):
// what its half-float records keep of S and the albedo, that every voxel finds its own record, that
// reading in pieces gives the whole medium's compact form, and that it renders the float grids'
// image within Monte Carlo error.

#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/medium/compact_attributes.h"
#include "libvdbappear/medium/compact_medium.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/render_image.h"
#include "libvdbappear/render/scene_description.h"

#include "support/medium_testing.h"
#include "support/render_testing.h"
#include "support/temp_dir.h"
#include "support/test_random.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cstring>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::math::half;

openvdb::Vec3s diagOf(const Mat3& S) { return toVec3s(sggxDiagonal(S)); }
openvdb::Vec3s offdiagOf(const Mat3& S) { return toVec3s(sggxOffDiagonal(S)); }

// S as the medium's float channels hold it.
Mat3 floatS(const Mat3& S) { return sggxMatrix(toVec3(diagOf(S)), toVec3(offdiagOf(S))); }

double sigmaOf(const Mat3& S, const Vec3& w) { return std::sqrt(std::max(0.0, w.dot(S * w))); }

// The largest relative error of sigma(w) = sqrt(w^T S w) over directions: random ones and S's own
// eigenvectors (a fibre's tangent is its smallest).
template <typename Approximate>
double largestSigmaError(const Mat3& S, const Approximate& approximate, test::TestRandom& random) {
  Eigen::SelfAdjointEigenSolver<Mat3> solver(S);
  double worst = 0;
  for (int k = 0; k < 203; ++k) {
    const Vec3 w = k < 3 ? Vec3(solver.eigenvectors().col(k)) : random.direction();
    const double exact = sigmaOf(S, w);
    worst = std::max(worst, std::abs(approximate(w) - exact) / exact);
  }
  return worst;
}

// Fibres and surfaces of every roughness from 0.01, in random orientations and at scales 1e-3..1e3.
std::vector<Mat3> testMatrices(test::TestRandom& random, double roughness) {
  std::vector<Mat3> matrices;
  for (int i = 0; i < 40; ++i) {
    const double scale = std::pow(10.0, 6 * random.uniform() - 3);
    matrices.push_back(floatS(scale * Sggx::fiberMatrix(random.direction(), roughness)));
    matrices.push_back(floatS(scale * Sggx::surfaceMatrix(random.direction(), roughness)));
  }
  return matrices;
}

// sigma(w) from the record errs by at most 2^-10 relative in every direction (the eigenvalues' 2^-11
// halved by the square root, plus the rotation's rounding) down to roughness 0.03; at 0.01, by at
// most 1/400 (measured 0.19%): sigma varies over an angle of about the roughness around the fibre, and
// the rotation's rounding (2^-15 a component) tilts the fibre by some 5e-5 radians. The record's S is
// positive definite. Negative control: S's six entries rounded to half floats err over 3 times as
// much at roughness 0.1 and below, and make fibres of roughness 0.01 indefinite.
TEST(CompactVoxel, SigmaErrsByHalfPrecisionInEveryDirectionAndSStaysPositiveDefinite) {
  test::TestRandom random(7);
  for (const double roughness : {0.01, 0.03, 0.1, 0.3, 1.0}) {
    double worst = 0, worst_rounded_entries = 0;
    int indefinite_rounded = 0;
    for (const Mat3& S : testMatrices(random, roughness)) {
      const CompactVoxel v = compactVoxel(openvdb::Vec3s(0.5f), diagOf(S), offdiagOf(S));
      worst = std::max(worst, largestSigmaError(S, [&](const Vec3& w) { return std::sqrt(wSwOf(v, w)); }, random));
      const Mat3 stored = sggxOf(v);
      EXPECT_TRUE(isPositiveDefinite(sggxDiagonal(stored), sggxOffDiagonal(stored))) << "roughness " << roughness;
      EXPECT_NEAR(wSwOf(v, Vec3(0.6, 0.0, 0.8)), Vec3(0.6, 0.0, 0.8).dot(stored * Vec3(0.6, 0.0, 0.8)),
                  1e-12 * stored.norm());  // wSwOf is the record's S
      // The control: each entry rounded to a half float.
      Mat3 rounded = S;
      for (int i = 0; i < 9; ++i) rounded.data()[i] = float(half(float(S.data()[i])));
      indefinite_rounded += !isPositiveDefinite(sggxDiagonal(rounded), sggxOffDiagonal(rounded));
      worst_rounded_entries =
          std::max(worst_rounded_entries, largestSigmaError(S, [&](const Vec3& w) { return sigmaOf(rounded, w); }, random));
    }
    EXPECT_LT(worst, roughness > 0.02 ? 1.0 / 1024 : 1.0 / 400) << "roughness " << roughness;
    if (roughness <= 0.1) EXPECT_GT(worst_rounded_entries, 3 * worst) << "the control, roughness " << roughness;
    if (roughness == 0.01) EXPECT_GT(indefinite_rounded, 0) << "the control makes thin fibres indefinite";
  }
}

// The albedo to half-float rounding: at most 2^-12 off in [0, 1].
TEST(CompactVoxel, AlbedoIsRoundedToHalfFloats) {
  test::TestRandom random(3);
  for (int i = 0; i < 1000; ++i) {
    const openvdb::Vec3s albedo(float(random.uniform()), float(random.uniform()), i % 2 ? 1.0f : 0.0f);
    const Rgb stored = albedoOf(compactVoxel(albedo, openvdb::Vec3s(1.0f), openvdb::Vec3s(0.0f)));
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(stored[c] - albedo[c]), 1.0 / 4096) << albedo;
  }
  const CompactVoxel isotropic = compactVoxel(openvdb::Vec3s(1.0f), openvdb::Vec3s(1.0f), openvdb::Vec3s(0.0f));
  EXPECT_LT((sggxOf(isotropic) - Mat3::Identity()).norm(), 1e-3);
}

// Every active density voxel finds its own record through its leaf, whatever the leaf's mask; the
// count of records is the count of active voxels.
TEST(CompactAttributes, EveryActiveVoxelFindsItsOwnRecord) {
  RandomMediumParams params;
  params.extent = 53;  // -26 .. 26: negative and odd index ranges
  params.seed = 5;
  const MediumPtr medium = makeRandomMedium(params);
  CompactAttributes attributes;
  attributes.add(*medium);
  EXPECT_EQ(attributes.voxelCount(), medium->density->activeVoxelCount());
  EXPECT_TRUE(attributes.hasAlbedo());
  EXPECT_TRUE(attributes.hasSggx());
  CompactAttributes::Accessor records(attributes);
  auto albedo = medium->albedo->getConstAccessor();
  auto diag = medium->sggx_diag->getConstAccessor();
  auto offdiag = medium->sggx_offdiag->getConstAccessor();
  std::size_t checked = 0;
  for (auto leaf = medium->density->tree().cbeginLeaf(); leaf; ++leaf)
    for (auto v = leaf->cbeginValueOn(); v; ++v) {
      const Coord ijk = v.getCoord();
      const CompactVoxel expected = compactVoxel(albedo.getValue(ijk), diag.getValue(ijk), offdiag.getValue(ijk));
      const CompactVoxel& found = records.at(*leaf, v.pos());
      EXPECT_EQ(std::memcmp(&expected, &found, sizeof(CompactVoxel)), 0) << ijk;
      ++checked;
    }
  EXPECT_EQ(checked, medium->density->activeVoxelCount());
  EXPECT_GT(checked, 10000u);
}

// The compact form of a file read in pieces is the compact form of the medium read whole: the same
// density tree and the same record for every voxel.
void expectSameCompactForm(const CompactMedium& a, const CompactMedium& b, const std::string& what) {
  ASSERT_TRUE(a.medium && b.medium) << what;
  const openvdb::FloatTree &ta = a.medium->density->tree(), &tb = b.medium->density->tree();
  EXPECT_EQ(ta.leafCount(), tb.leafCount()) << what;
  EXPECT_EQ(ta.activeVoxelCount(), tb.activeVoxelCount()) << what;
  ASSERT_EQ(bool(a.attributes), bool(b.attributes)) << what;
  std::optional<CompactAttributes::Accessor> ra, rb;
  if (a.attributes) ra.emplace(*a.attributes), rb.emplace(*b.attributes);
  std::size_t differences = 0;
  for (auto leaf = ta.cbeginLeaf(); leaf; ++leaf) {
    const auto* other = tb.probeConstLeaf(leaf->origin());
    if (!other || other->getValueMask() != leaf->getValueMask()) {
      ++differences;
      continue;
    }
    for (auto v = leaf->cbeginValueOn(); v; ++v) {
      differences += std::memcmp(leaf->buffer().data() + v.pos(), other->buffer().data() + v.pos(), sizeof(float)) != 0;
      if (ra) differences += std::memcmp(&ra->at(*leaf, v.pos()), &rb->at(*other, v.pos()), sizeof(CompactVoxel)) != 0;
    }
  }
  EXPECT_EQ(differences, 0u) << what;
}

TEST(CompactMedium, ReadInPiecesIsTheWholeMediumMadeCompact) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 53;
  params.seed = 8;
  writeMedium(*makeRandomMedium(params), dir.path("random.vdb"), "test");
  params.extent = 24;
  writeMedium(*test::spreadCopies(*makeRandomMedium(params), {Coord(0, -300, -300), Coord(5, 140, 150), Coord(0, 400, -150)}),
              dir.path("spread.vdb"), "test");
  params.sggx = false;
  writeMedium(*makeRandomMedium(params), dir.path("albedo_only.vdb"), "test");
  params.albedo = false;
  writeMedium(*makeRandomMedium(params), dir.path("density_only.vdb"), "test");
  for (const char* name : {"random.vdb", "spread.vdb", "albedo_only.vdb", "density_only.vdb"}) {
    const std::string path = dir.path(name);
    std::string why_not;
    const auto whole = compactMedium(readMedium(path), &why_not);
    ASSERT_TRUE(whole) << name << ": " << why_not;
    const auto pieces = readCompactMedium(path, {}, 5'000'000, &why_not);  // 5 MB: several pieces
    ASSERT_TRUE(pieces) << name << ": " << why_not;
    if (std::string(name) != "density_only.vdb") EXPECT_GE(pieces->pieces, 3) << name;
    expectSameCompactForm(*whole, *pieces, name);
    EXPECT_EQ(bool(whole->attributes), std::string(name) != "density_only.vdb") << name;
  }
  // The golden twill, one piece.
  const std::string twill = std::string(GOLDEN_DIR) + "/twill24.vdb";
  std::string why_not;
  const auto pieces = readCompactMedium(twill, {}, 1'000'000'000, &why_not);
  ASSERT_TRUE(pieces) << why_not;
  EXPECT_EQ(pieces->pieces, 1);
  expectSameCompactForm(*compactMedium(readMedium(twill), &why_not), *pieces, "twill24");
}

// What the compact form does not hold is rendered from the grids: the reason names the grid.
TEST(CompactMedium, MediaWithOtherRenderedGridsOrTilesAreNotMadeCompact) {
  test::TempDir dir;
  RandomMediumParams params;
  params.extent = 20;
  const auto reason = [&](const MediumPtr& medium) {
    const std::string path = dir.path("m.vdb");
    writeMedium(*medium, path, "test");
    std::string whole_why, pieces_why;
    EXPECT_FALSE(compactMedium(readMedium(path), &whole_why));
    EXPECT_FALSE(readCompactMedium(path, {}, 1'000'000'000, &pieces_why));
    EXPECT_EQ(whole_why, pieces_why);
    return whole_why;
  };
  params.hg_g = true;
  EXPECT_NE(reason(makeRandomMedium(params)).find("hg_g"), std::string::npos);
  params.hg_g = false;
  MediumPtr emitting = makeRandomMedium(params);
  auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*emitting, grid_names::kEmission, openvdb::Vec3s(0.0f));
  emission->tree().setValueOn(Coord(1, 2, 3), openvdb::Vec3s(1.0f));
  emitting->other_grids.push_back(emission);
  EXPECT_NE(reason(emitting).find("'emission'"), std::string::npos);
  const std::string lobes = reason(test::multiLobeTwill(24, 2, 2, 2, 2));
  EXPECT_NE(lobes.find("'cluster', 'lobe0_diag'"), std::string::npos) << lobes;
  MediumPtr tiled = makeRandomMedium(params);
  tiled->density->tree().addTile(1, Coord(64, 64, 64), 1.0f, true);
  EXPECT_NE(reason(tiled).find("active tiles"), std::string::npos);
}

// The compact form of a medium it holds (the test fails otherwise).
CompactMedium compactFormOf(const MediumPtr& medium) {
  std::string why_not;
  const auto compact = compactMedium(medium, &why_not);
  EXPECT_TRUE(compact) << why_not;
  return compact ? *compact : CompactMedium{};
}

// The view of the compact form: extinction within 2^-10 of the float grids' at nearest and trilinear
// lookups, albedo within 2^-12, and a majorant that bounds the compact medium (no violation in a render).
TEST(CompactMediumView, LooksUpWhatTheFloatGridsHoldToHalfPrecision) {
  RandomMediumParams params;
  params.extent = 40;
  params.seed = 11;
  const MediumPtr medium = makeRandomMedium(params);
  const CompactMedium compact = compactFormOf(medium);
  ASSERT_TRUE(compact.medium);
  for (const Interpolation interp : {Interpolation::kNearest, Interpolation::kTrilinear}) {
    const MediumView full_view(medium, interp), compact_view(compact, interp);
    EXPECT_TRUE(compact_view.compact());
    EXPECT_FALSE(full_view.compact());
    EXPECT_EQ(compact_view.phaseSource(), PhaseSource::kSggx);
    const auto full = full_view.lookup(), small = compact_view.lookup();
    test::TestRandom random(2);
    const Aabb box = full_view.worldBounds();
    double worst_sigma = 0, worst_albedo = 0;
    int scattering = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 p = box.lo + Vec3(random.uniform(), random.uniform(), random.uniform()).cwiseProduct(box.extent());
      const Vec3 w = random.direction();
      const double a = full->extinction(p, w), b = small->extinction(p, w);
      if (a == 0) {
        EXPECT_EQ(b, 0) << "empty space stays empty";
        continue;
      }
      worst_sigma = std::max(worst_sigma, std::abs(b - a) / a);
      ScatteringFunction fa, fb;
      full->scattering(p, &fa);
      small->scattering(p, &fb);
      if (fa.lobeCount() == 0) continue;
      ASSERT_EQ(fb.lobeCount(), 1);
      worst_albedo = std::max(worst_albedo, (fa.weight(0) - fb.weight(0)).abs().maxCoeff());
      ++scattering;
    }
    EXPECT_GT(scattering, 1000);
    EXPECT_LT(worst_sigma, 1.0 / 1024) << interpolationName(interp);
    EXPECT_LT(worst_albedo, 1.0 / 4096 + 1e-7) << interpolationName(interp);
  }
}

test::Render renderView(const std::shared_ptr<const MediumView>& view, std::uint64_t seed) {
  SceneDescription description;
  description.lights = {{{"type", "env"}, {"radiance", 0.3}}, {{"type", "sun"}, {"direction", {0.3, 0.2, -1}}, {"strength", 3}}};
  description.render = test::small(24, 24, seed);
  description.view = "+z";
  const RenderScene scene = buildRenderScene(description, view, {});
  const PinholeCamera camera(cameraOf(description, view.get()), 24, 24);
  return test::summarize(renderImage(scene, camera, description.render));
}

// The twill rendered from its compact form and from its float grids (other seeds): the same image
// within Monte Carlo error, mean and every pixel; no majorant violation.
TEST(CompactMediumView, RendersTheFloatGridsImageWithinMonteCarloError) {
  WeaveParams weave;
  weave.resolution = 48;
  weave.yarns = 2;
  const MediumPtr twill = makeWeave(weave);
  const CompactMedium compact = compactFormOf(twill);
  ASSERT_TRUE(compact.medium);
  for (const Interpolation interp : {Interpolation::kNearest, Interpolation::kTrilinear}) {
    const test::Render full = renderView(std::make_shared<MediumView>(twill, interp), 1);
    const test::Render small = renderView(std::make_shared<MediumView>(compact, interp), 2);
    EXPECT_GT(full.mean, 0.01);
    test::expectSameImage(full, small, interpolationName(interp));
    EXPECT_EQ(small.result.tracking.majorant_violations, 0u);
  }
}

}  // namespace
}  // namespace vdbappear
