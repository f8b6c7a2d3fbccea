// The whole prefiltering at one scale (libvdbappear/prefilter/displacement_prefilter.h, §4.7.1 of
// the displacement chapter): a flat map needs no scaling (T = S = 1); on a bumpy Lambertian map
// interreflection only adds light (S_ir >= S bin by bin, the same base positions); bad settings throw.
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/prefilter/displacement_prefilter.h"
#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"
#include "libvdbappear/util/error.h"

#include "support/brdf_chi2.h"
#include "support/chi2_test.h"
#include "support/height_fields.h"
#include "support/prefilter_settings.h"
#include "support/test_random.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace vdbappear {
namespace {

// 32^2 cells of 0.01 at height 0.05.
HeightField flatMap() {
  HeightField flat(32, 32, 0.01);
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) flat.at(i, j) = 0.05;
  return flat;
}

TEST(DisplacementPrefilter, FlatMapNeedsNoScaling) {
  const HeightField flat = flatMap();
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1));
  const PrefilteredSurface p = prefilterDisplacement(flat, base, test::smallPrefilterSettings());
  EXPECT_EQ(p.height.cellsX(), 4);
  EXPECT_EQ(p.ndfs.size(), 16u);
  for (const Rgb& t : p.scaling.T.values) EXPECT_LT((t - 1).abs().maxCoeff(), 1e-3) << t.transpose();
  for (const Rgb& s : p.scaling.S.values) EXPECT_LT((s - 1).abs().maxCoeff(), 2e-3) << s.transpose();
}

// S_ir / S of the red channel, averaged over S's bins; with `every_bin`, S_ir >= S in each bin too.
double interreflectionGain(const HeightField& map, const MicrofacetBrdf& base, DisplacementPrefilterSettings s,
                           bool every_bin) {
  s.scaling = ScalingKind::Shadowing;
  const PrefilteredSurface shadowing = prefilterDisplacement(map, base, s);
  s.scaling = ScalingKind::Interreflection;
  const PrefilteredSurface interreflection = prefilterDisplacement(map, base, s);
  const std::vector<Rgb>&S = shadowing.scaling.S.values, &S_ir = interreflection.scaling.S.values;
  double gain = 0;
  for (std::size_t k = 0; k < S.size(); ++k) {
    if (every_bin) EXPECT_GE(S_ir[k][0], S[k][0]) << k;
    gain += S_ir[k][0] / S[k][0] / double(S.size());
  }
  return gain;
}

TEST(DisplacementPrefilter, InterreflectionOnlyAddsLight) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb::Zero(), Rgb::Constant(0.8));
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  // Albedo 0.8 on slopes near 1: a visible share of the light bounces. Measured: 1.16 on average.
  EXPECT_GT(interreflectionGain(bumpy, base, s, true), 1.05);
  // With the jackknife on S's bins (a different non-linear function of the 4 positions in each bin,
  // which can swap a close pair), on average. Measured: 1.15.
  s.factorization.jackknife = true;
  EXPECT_GT(interreflectionGain(bumpy, base, s, false), 1.05);
}

// A bin's positions that fall in one coarse cell are independent estimates: on a map of one coarse
// cell, the variance of S's bins over seeds falls with 16 positions (measured: 7.8 times, a ratio's
// bins; 16 for a mean). Keyed by the cell alone (before), the 16 were one estimate counted 16
// times: the same S as one position's, the same variance.
TEST(DisplacementPrefilter, PositionsInOneCellAreIndependentEstimates) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb::Zero(), Rgb::Constant(0.8));
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.factor = 32;
  s.samples_per_side = 4;
  s.scaling = ScalingKind::Shadowing;
  const auto spread_over_seeds = [&](int positions) {
    s.factorization.positions_per_angular_bin = positions;
    std::vector<std::vector<double>> bins;  // per seed, S's red channel
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      s.seed = s.factorization.seed = seed;
      bins.emplace_back();
      for (const Rgb& v : prefilterDisplacement(bumpy, base, s).scaling.S.values) bins.back().push_back(v[0]);
    }
    double variance = 0;  // over seeds, averaged over the bins
    for (std::size_t k = 0; k < bins[0].size(); ++k) {
      double mean = 0, square = 0;
      for (const auto& b : bins) mean += b[k] / double(bins.size());
      for (const auto& b : bins) square += (b[k] - mean) * (b[k] - mean) / double(bins.size() - 1);
      variance += square / double(bins[0].size());
    }
    return variance;
  };
  const double one = spread_over_seeds(1), many = spread_over_seeds(16);
  std::printf("variance of S over seeds: %.3g at 1 position, %.3g at 16 in the one cell\n", one, many);
  EXPECT_GT(one, 0);
  EXPECT_LT(many, one / 4);
}

// Tables over a convex base (DisplacementPrefilterSettings::base_curvature): on a map of one coarse
// cell, h_low is one facet that shadows and masks nothing, so R's denominator is the plane's, while
// over the curved base the original's rays rise above the map and clear at least what they clear on
// the plane (the same positions, paths and seeds): every S bin at least the plane's, and more where
// a bump hides the light or the view. A flat map still needs no scaling; a negative curvature is
// refused.
TEST(DisplacementPrefilter, TablesOverAConvexBaseShadowAndMaskLess) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb::Zero(), Rgb::Constant(0.8));
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.factor = 32;
  s.scaling = ScalingKind::Shadowing;
  const std::vector<Rgb> plane = prefilterDisplacement(bumpy, base, s).scaling.S.values;
  s.base_curvature = 10;  // a sphere of radius 10 cells: a bump of 17 cells falls 0.036 away, as high as it is
  const std::vector<Rgb> curved = prefilterDisplacement(bumpy, base, s).scaling.S.values;
  ASSERT_EQ(plane.size(), curved.size());
  double gain = 0;
  for (std::size_t k = 0; k < plane.size(); ++k) {
    EXPECT_GE(curved[k][0], plane[k][0] * (1 - 1e-9)) << k;
    gain = std::max(gain, curved[k][0] / plane[k][0]);
  }
  std::printf("S over a base of radius 10 cells: up to %.3f times the plane's\n", gain);
  EXPECT_GT(gain, 1.05);

  const HeightField flat = flatMap();
  s.factor = 8;
  const PrefilteredSurface p = prefilterDisplacement(flat, base, s);
  for (const Rgb& v : p.scaling.S.values) EXPECT_LT((v - 1).abs().maxCoeff(), 2e-3) << v.transpose();
  s.base_curvature = -1;
  EXPECT_THROW(prefilterDisplacement(flat, base, s), std::invalid_argument);
}

TEST(DisplacementPrefilter, RefusesAFactorThatDoesNotDivideTheMap) {
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb::Zero(), Rgb::Constant(0.8));
  DisplacementPrefilterSettings s = test::smallPrefilterSettings();
  s.factor = 6;
  EXPECT_THROW(prefilterDisplacement(HeightField(32, 32, 0.01), base, s), std::invalid_argument);
}

// A bumpy map's model (facets up to 51 degrees) and its coarse cell (1, 2) of 4 x 4 at x.
struct BumpyModel {
  HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.002, 3);
  MicrofacetBrdf base{MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1)};
  PrefilteredSurface surface = prefilterDisplacement(bumpy, base, test::smallPrefilterSettings());
  Point2 x{0.3, 0.6};
  MultiLobeBrdf cell{surface.ndfs[1 + 4 * 2], base};
};

// The chi-square test's settings for the renderer's SVBRDF: draws that fail are absorbed.
test::Chi2Options samplingOptions(std::uint64_t seed, int test_count) {
  test::Chi2Options o;
  o.test_count = test_count;
  o.seed = seed;
  o.sample_count = 200'000;
  o.bins.tolerance = 1e-5;
  o.bins.max_depth = 4;
  o.absorbed_samples = true;
  return o;
}

// The renderer's SVBRDF (prefilter/prefiltered_brdf.h) on a curved base: sample() draws wi with the
// density pdf() over the whole sphere, f'_low's lobes above the base horizon and their mirror
// images below it, for a view above the horizon and one below it (a sphere's silhouette); its
// weight is eval |cos theta_i| / pdf; eval is continuous across the horizon and lights facets
// below it (a plane's map would shadow them; beyond a sphere's terminator they are lit).
TEST(PrefilteredBrdf, SamplingFollowsItsPdfAboveAndBelowTheHorizon) {
  const BumpyModel m;
  const PrefilteredBrdf f(m.surface, m.base, PrefilteredBrdf::Base::kCurved);
  const Point2& x = m.x;
  test::TestRandom random(5);
  std::uint64_t seed = 40;
  for (const Vec3& wo : {Vec3(0.3, 0.1, 1).normalized(), Vec3(0.95, 0.2, -0.04).normalized()}) {
    const test::Chi2Result r = test::chi2TestBrdfSampling(
        [&](double u_lobe, const Point2& u) { return f.sample(x, wo, u_lobe, u); },
        [&](const Vec3& wi) { return f.pdf(x, wo, wi); }, samplingOptions(++seed, 2));
    EXPECT_TRUE(r.passed) << r.summary;
    EXPECT_LT(r.invalid_fraction, 0.5) << r.summary;  // the view below the horizon is reflected too
    int below = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const BrdfSample s = f.sample(x, wo, random.uniform(), random.point2());
      if (s.pdf == 0) continue;
      below += s.wi.z() < 0;
      const Rgb expected = f.eval(x, s.wi, wo) * std::abs(s.wi.z()) / f.pdf(x, wo, s.wi);
      EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.maxCoeff()));
    }
    EXPECT_GT(below, 5);
    EXPECT_LT(below, 60);  // 1/16 of 400 draws, where the lobes reach
  }
  double lit_below = 0;
  for (int k = 0; k < 16; ++k) {
    const double phi = 2 * M_PI * k / 16, wo_z = 0.6;
    const Vec3 wo(0.8 * std::cos(phi + 2), 0.8 * std::sin(phi + 2), wo_z);
    const auto at = [&](double z) -> Vec3 { return Vec3(std::cos(phi), std::sin(phi), 0) * std::sqrt(1 - z * z) + Vec3(0, 0, z); };
    const Rgb above = f.eval(x, at(1e-7), wo), across = f.eval(x, at(-1e-7), wo);
    EXPECT_LT((above - across).abs().maxCoeff(), 1e-4 * (1e-9 + above.maxCoeff())) << phi;
    lit_below += f.eval(x, at(-0.1), wo).maxCoeff();
  }
  EXPECT_GT(lit_below, 0);
}

// On a plane, sample() folds f'_low's lobe draws that fall below the base horizon (where Eq. (4.5)
// is zero) onto their mirror images above it: wi follows pdf() over the upper hemisphere, the
// weight is eval cos theta_i / pdf, and the mean weight, the integral of f_low cos theta_i, is what
// cosine-weighted directions estimate (a draw of no value was absorbed before). The weights spread
// less than those of the unfolded draws (MultiLobeBrdf::sample times T S), which lose every draw
// below the horizon: the negative control.
TEST(PrefilteredBrdf, SamplingOnAPlaneFoldsDrawsBelowTheHorizonAbove) {
  const BumpyModel m;
  const PrefilteredBrdf f(m.surface, m.base, PrefilteredBrdf::Base::kPlane);
  const Point2& x = m.x;
  const MultiLobeBrdf& cell = m.cell;
  const Vec3 wo = Vec3(0.2, -0.85, 0.5).normalized();  // 60 degrees from the normal
  const test::Chi2Result r = test::chi2TestBrdfSampling(
      [&](double u_lobe, const Point2& u) { return f.sample(x, wo, u_lobe, u); },
      [&](const Vec3& wi) { return f.pdf(x, wo, wi); }, samplingOptions(71, 1));
  EXPECT_TRUE(r.passed) << r.summary;

  test::TestRandom random(9);
  const int n = 200'000;
  double folded = 0, folded2 = 0, unfolded = 0, unfolded2 = 0, cosine = 0, cosine2 = 0;
  int absorbed_before = 0;
  for (int i = 0; i < n; ++i) {
    const double u_l = random.uniform();
    const Point2 u = random.point2();
    const BrdfSample s = f.sample(x, wo, u_l, u);
    if (s.pdf > 0) {
      ASSERT_GT(s.wi.z(), 0);
      const Rgb expected = f.eval(x, s.wi, wo) * s.wi.z() / f.pdf(x, wo, s.wi);
      ASSERT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.maxCoeff()));
    }
    const double w = s.pdf > 0 ? s.weight.mean() : 0.0;
    folded += w, folded2 += w * w;
    const BrdfSample b = cell.sample(wo, u_l, u);  // the same draw, unfolded
    absorbed_before += !(b.pdf > 0);
    const double v = b.pdf > 0 ? (b.weight * f.scalingOnTile(x, b.wi, wo, {})).mean() : 0.0;
    unfolded += v, unfolded2 += v * v;
    const Vec3 wi = sampleCosineHemisphere(random.point2());
    const double c = wi.z() > 0 ? f.eval(x, wi, wo).mean() * kPi : 0.0;  // f cos / (cos / pi)
    cosine += c, cosine2 += c * c;
  }
  const auto variance = [&](double sum, double sum2) { return sum2 / n - (sum / n) * (sum / n); };
  const double error = std::sqrt((variance(folded, folded2) + variance(cosine, cosine2)) / n);
  std::printf("albedo: folded %.5f, unfolded %.5f, cosine %.5f +- %.5f; weight std folded %.4f, unfolded %.4f; "
              "draws absorbed unfolded %.1f%%\n", folded / n, unfolded / n, cosine / n, error,
              std::sqrt(variance(folded, folded2)), std::sqrt(variance(unfolded, unfolded2)), 100.0 * absorbed_before / n);
  EXPECT_NEAR(folded / n, cosine / n, 4 * error);
  EXPECT_NEAR(unfolded / n, cosine / n, 4 * std::sqrt((variance(unfolded, unfolded2) + variance(cosine, cosine2)) / n));
  EXPECT_GT(absorbed_before, n / 20);  // the control loses draws below the horizon
  EXPECT_LT(variance(folded, folded2), 0.8 * variance(unfolded, unfolded2));

  // Over a squeezed tile the weight is eval cos theta_i / pdf too.
  const TileStretch squeezed = TileStretch::diagonal(0.6, 1);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const BrdfSample s = f.sample(x, wo, random.uniform(), random.point2(), squeezed);
    if (!(s.pdf > 0)) continue;
    ++checked;
    ASSERT_GT(s.wi.z(), 0);
    const Rgb expected = f.eval(x, s.wi, wo, squeezed) * s.wi.z() / f.pdf(x, wo, s.wi);
    EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.maxCoeff()));
  }
  EXPECT_GT(checked, 300);
}

// A view below a curved base's horizon (prefilter/prefiltered_brdf.h): f_low is continuous across
// the horizon, and below it, where S is read at the horizon node, it follows the mean of the lobes
// in view (MultiLobeBrdf::visibleMean) down each azimuth, on the square tile and on a squeezed one.
// Eq. (4.5)'s sum alone, which fades as fewer lobes face the viewer, is the negative control.
TEST(PrefilteredBrdf, ViewBelowACurvedBaseFollowsTheLobesInView) {
  const BumpyModel m;
  const PrefilteredSurface& surface = m.surface;
  const PrefilteredBrdf f(surface, m.base, PrefilteredBrdf::Base::kCurved);
  const Point2& x = m.x;
  const MultiLobeBrdf& cell = m.cell;
  const Vec3 wi = Vec3(0.2, 0.3, 0.9).normalized();
  int compared = 0;
  double largest_fade = 0;
  for (const TileStretch& stretch : {TileStretch(), TileStretch::diagonal(0.6, 1)}) {
    for (int k = 0; k < 16; ++k) {
      const double phi = 2 * M_PI * k / 16;
      const auto at = [&](double z) -> Vec3 { return Vec3(std::cos(phi), std::sin(phi), 0) * std::sqrt(1 - z * z) + Vec3(0, 0, z); };
      const Rgb above = f.eval(x, wi, at(1e-7), stretch), across = f.eval(x, wi, at(-1e-7), stretch);
      EXPECT_LT((above - across).abs().maxCoeff(), 1e-4 * (1e-9 + above.maxCoeff())) << phi;
      const Vec3 near = at(-0.05), far = at(-0.25);
      const double model = f.eval(x, wi, far, stretch)[0] / f.eval(x, wi, near, stretch)[0];
      const double in_view = cell.visibleMean(wi, far, stretch)[0] / cell.visibleMean(wi, near, stretch)[0];
      if (!std::isfinite(model) || !std::isfinite(in_view) || model == 0) continue;
      ++compared;
      EXPECT_NEAR(model, in_view, 1e-9 * in_view) << phi;
      const double area_alone = cell.projected(wi, far, stretch)[0] / cell.projected(wi, near, stretch)[0];
      largest_fade = std::max(largest_fade, std::abs(area_alone / in_view - 1));
    }
  }
  EXPECT_GT(compared, 8);
  EXPECT_GT(largest_fade, 0.1);  // measured: up to 10.9 (27 azimuths compared)
}

// docs/displacement.md §6: what is written is read back, to float precision, with the BRDF and the
// manifest's scalars; a missing part or a manifest of another kind is refused naming the file.
TEST(PrefilteredSurfaceFile, RoundTripsAndRefusesBrokenSets) {
  const HeightField bumpy = test::sinusoidHeightField(32, 0.01, {17.0, 9.0, 5.0}, 0.001, 3);
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::Beckmann, 0.25), Rgb(0.9, 0.5, 0.2), Rgb(0.1, 0.2, 0.3));
  PrefilteredSurfaceFile written{prefilterDisplacement(bumpy, base, test::smallPrefilterSettings()), base, {"map.exr", 8, 0.32, 2.0, ScalingKind::Shadowing}};
  const test::TempDir dir;
  const std::string manifest = dir.path("bumpy_8x.json");
  writePrefilteredSurface(written, manifest, {{"seed", 1}});
  for (const char* part : {"height", "lobes", "T", "S"})
    EXPECT_TRUE(std::filesystem::exists(dir.path(std::string("bumpy_8x.") + part + ".exr"))) << part;
  const PrefilteredSurfaceFile read = readPrefilteredSurface(manifest);
  EXPECT_EQ(read.info.source, "map.exr");
  EXPECT_EQ(read.info.factor, 8);
  EXPECT_EQ(read.info.scaling, ScalingKind::Shadowing);
  EXPECT_DOUBLE_EQ(read.info.height_scale, 2.0);
  EXPECT_EQ(read.base.distribution().kind(), MicrofacetKind::Beckmann);
  EXPECT_DOUBLE_EQ(read.base.distribution().alpha(), 0.25);
  EXPECT_TRUE((read.base.specular() == base.specular()).all());
  const HeightField& h = read.surface.height;
  ASSERT_EQ(h.cellsX(), 4);
  EXPECT_NEAR(h.cellSize(), 0.08, 1e-12);
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) EXPECT_NEAR(h.at(i, j), written.surface.height.at(i, j), 1e-6 * 2);
  ASSERT_EQ(read.surface.ndfs.size(), 16u);
  for (std::size_t c = 0; c < 16; ++c) {
    const Vec3 w = Vec3(0.3, -0.2, 1).normalized();
    EXPECT_NEAR(read.surface.ndfs[c](w), written.surface.ndfs[c](w), 1e-4 * written.surface.ndfs[c](w)) << c;
  }
  const Vec3 wi = Vec3(0.5, 0.1, 0.8).normalized(), wo = Vec3(-0.2, 0.4, 0.9).normalized();
  const Point2 x(0.3, 0.7);
  EXPECT_LT((read.surface.scaling(x, wi, wo) - written.surface.scaling(x, wi, wo)).abs().maxCoeff(), 1e-5);

  std::filesystem::remove(dir.path("bumpy_8x.S.exr"));
  try {
    readPrefilteredSurface(manifest);
    ADD_FAILURE() << "a missing part was accepted";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("bumpy_8x.S.exr: missing"), std::string::npos) << e.what();
  }
  std::ofstream(dir.path("other.json")) << R"({"format": "something else"})";
  EXPECT_THROW(readPrefilteredSurface(dir.path("other.json")), MediumError);
}

}  // namespace
}  // namespace vdbappear
