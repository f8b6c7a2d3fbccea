// Patch NDFs as vMF mixtures (Eq. 4.2-4.4 of the displacement chapter; libvdbappear/surface/
// patch_ndf.h, vmf_ndf.h): the vMF lobe's normalisation and sampling, recovery of a known mixture,
// and the six-lobe fit of a bumpy patch against the histogram of its micro-normals, with one lobe
// as the negative control.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"
#include "libvdbappear/surface/patch_ndf.h"

#include "support/brdf_chi2.h"
#include "support/chi2_test.h"
#include "support/height_fields.h"
#include "support/sphere_quadrature.h"
#include "support/test_random.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace vdbappear {
namespace {

TEST(Vmf, LobeIntegratesToOneAndSamplesItself) {
  std::uint64_t seed = 30;
  for (double kappa : {1e-9, 0.1, 5.0, 100.0, 1e4}) {
    const Vec3 mu = Vec3(0.3, -0.2, 0.9).normalized();
    // gamma depends on w . mu only: int = 2 pi int_{-1}^{1} gamma(t) dt.
    const double integral = 2 * kPi * boost::math::quadrature::gauss_kronrod<double, 15>::integrate(
                                          [&](double t) { return vmf(Frame::fromNormal(mu).toWorld(Vec3(std::sqrt(1 - t * t), 0, t)), kappa, mu); },
                                          -1.0, 1.0, 25, 1e-12);
    EXPECT_NEAR(integral, 1, 1e-8) << "kappa " << kappa;
    if (kappa > 1e3) continue;  // narrower than a bin
    test::Chi2Options o;
    o.bins.frame = Frame::fromNormal(mu);
    o.test_count = 4;
    o.seed = ++seed;
    o.sample_count = 200'000;
    o.bins.tolerance = 1e-7;
    o.bins.max_depth = 8;
    const test::Chi2Result r = test::chi2TestDirections([&](const Point2& u) { return sampleVmf(kappa, mu, u); },
                                                        [&](const Vec3& w) { return vmf(w, kappa, mu); }, o);
    EXPECT_TRUE(r.passed) << "kappa " << kappa << ": " << r.summary;
  }
}

TEST(Vmf, FitRecoversAKnownMixture) {
  test::TestRandom random(4);
  const Vec3 mu1 = Vec3(0.4, 0.1, 0.9).normalized(), mu2 = Vec3(-0.3, 0.2, 0.93).normalized();
  std::vector<Vec3> d;
  for (int n = 0; n < 30000; ++n)
    d.push_back(random.uniform() < 0.3 ? sampleVmf(40, mu1, random.point2()) : sampleVmf(200, mu2, random.point2()));
  VmfFitSettings settings;
  settings.lobes = 2;
  const VmfMixture fit = fitVmfMixture(d, std::vector<double>(d.size(), 1.0), settings);
  ASSERT_EQ(fit.lobes.size(), 2u);
  const bool first_is_wide = fit.lobes[0].kappa < fit.lobes[1].kappa;
  const VmfLobe& wide = fit.lobes[first_is_wide ? 0 : 1];
  const VmfLobe& narrow = fit.lobes[first_is_wide ? 1 : 0];
  EXPECT_NEAR(wide.amplitude, 0.3, 0.01);
  EXPECT_NEAR(wide.kappa, 40, 40 * 0.05);
  EXPECT_NEAR(narrow.kappa, 200, 200 * 0.05);
  EXPECT_LT(std::acos(std::min(1.0, wide.mu.dot(mu1))), 0.01);
  EXPECT_LT(std::acos(std::min(1.0, narrow.mu.dot(mu2))), 0.005);
}

// A bumpy height field: sinusoids of periods 5 to 40 cells with random phases and directions.
HeightField bumpyField(int cells, std::uint64_t seed) {
  return test::sinusoidHeightField(cells, 0.01, {40.0, 23.0, 11.0, 5.0}, 0.00015, seed);
}

// Total variation between the micro-normals' histogram (its bins hold int_bin D cos theta dw,
// Eq. 4.2) and the fitted D cos theta integrated over the same bins.
double histogramDistance(const std::vector<Vec3>& normals, const VmfMixture& ndf, double* projected_area) {
  test::SphereGrid bins;
  bins.theta_cells = 20;  // cos theta in steps of 0.1
  bins.phi_cells = 24;
  bins.tolerance = 1e-6;
  bins.max_depth = 6;
  std::vector<double> observed(std::size_t(bins.theta_cells * bins.phi_cells), 0.0);
  for (const Vec3& n : normals) {
    const int i = std::min(bins.theta_cells - 1, int((n.z() + 1) / 2 * bins.theta_cells));
    double phi = std::atan2(n.y(), n.x());
    if (phi < 0) phi += 2 * kPi;
    const int j = std::min(bins.phi_cells - 1, int(phi / (2 * kPi) * bins.phi_cells));
    observed[std::size_t(i * bins.phi_cells + j)] += 1.0 / double(normals.size());
  }
  double distance = 0;
  *projected_area = 0;
  for (int i = 0; i < bins.theta_cells; ++i)
    for (int j = 0; j < bins.phi_cells; ++j) {
      const double c0 = -1 + 2.0 * i / bins.theta_cells, c1 = c0 + 2.0 / bins.theta_cells;
      const double p0 = 2 * kPi * j / bins.phi_cells, p1 = p0 + 2 * kPi / bins.phi_cells;
      const double fitted = c1 <= 0 ? 0 : test::integrateCell([&](const Vec3& w) { return ndf(w) * std::max(0.0, w.z()); },
                                                              bins, c0, c1, p0, p1);
      *projected_area += fitted;
      distance += 0.5 * std::abs(observed[std::size_t(i * bins.phi_cells + j)] - fitted);
    }
  return distance;
}

TEST(PatchNdf, SixLobesFollowTheMicroNormalsHistogram) {
  const HeightField field = bumpyField(64, 9);
  const std::vector<Vec3> normals = patchMicroNormals(field, 16, 16, 32, 4);
  ASSERT_EQ(normals.size(), std::size_t(32 * 32 * 16));
  double six_area = 0, one_area = 0;
  const double six = histogramDistance(normals, fitPatchNdf(normals, {}), &six_area);
  VmfFitSettings single;
  single.lobes = 1;
  const double one = histogramDistance(normals, fitPatchNdf(normals, single), &one_area);
  // Measured: 0.043 for six lobes, 0.100 for one (the histogram's own sampling noise is part of both).
  EXPECT_LT(six, 0.1);
  EXPECT_LT(six, 0.6 * one);  // the negative control: one lobe misses the patch's shape
  EXPECT_NEAR(six_area, 1, 0.02);  // Eq. (4.3); measured 1.00001
  EXPECT_LT(one_area, 1.02);
}

TEST(PatchNdf, FlatPatchIsOneNarrowLobeAlongTheNormal) {
  HeightField tilted(8, 8, 0.1);
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) tilted.at(i, j) = 0.5 * i * 0.1;  // slope 0.5 along x
  const VmfMixture ndf = fitPatchNdf(patchMicroNormals(tilted, 0, 0, 8, 2), {});
  ASSERT_GE(ndf.lobes.size(), 1u);
  double amplitude = 0;
  for (const VmfLobe& lobe : ndf.lobes) {
    EXPECT_TRUE(lobe.mu.isApprox(Vec3(-0.5, 0, 1).normalized(), 1e-9));
    EXPECT_GE(lobe.kappa, 1e4);
    amplitude += lobe.amplitude;
  }
  EXPECT_NEAR(amplitude, std::sqrt(1.25), 1e-9);  // int D dw = 1 / cos theta_m
}

// Eq. (4.5) for the NDF of a tilted plane, D = delta(w - mu) / cos theta_mu (a narrow lobe of that
// mass): rho(wi, wo) = f(R_mu wi, R_mu wo) <mu, wi> / (cos theta_i cos theta_mu). For mu = +z it is f.
TEST(MultiLobeBrdf, NarrowLobeIsTheBaseBrdfSeenThroughItsNormal) {
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::Beckmann, 0.3), Rgb(0.9, 0.6, 0.3), Rgb(0.1, 0.2, 0.3));
  test::TestRandom random(12);
  for (const Vec3& mu : {Vec3(0, 0, 1), Vec3(0.3, -0.2, 1).normalized()}) {
    VmfMixture ndf;
    ndf.lobes.push_back({1 / mu.z(), 1e7, mu});
    const MultiLobeBrdf rho(ndf, base);
    const Frame frame = Frame::fromNormal(mu);
    for (int trial = 0; trial < 50; ++trial) {
      Vec3 wi = random.direction(), wo = random.direction();
      wi.z() = std::abs(wi.z()) + 0.2;
      wo.z() = std::abs(wo.z()) + 0.2;
      wi.normalize();
      wo.normalize();
      const Rgb expected = base.eval(frame.toLocal(wo), frame.toLocal(wi)) * std::max(0.0, mu.dot(wi)) / (wi.z() * mu.z());
      EXPECT_LT((rho.eval(wi, wo) - expected).abs().maxCoeff(), 2e-3 * (expected.maxCoeff() + 0.01)) << mu.transpose();
    }
  }
}

// A Lambertian base seen along the macro-normal: rho(z, z) = kd / pi int <w, z> D(w) dw = kd / pi
// by Eq. (4.3), for the fitted NDF of a bumpy patch (to the fit's projected area and the micro-normals
// whose horizon hides z, none here). Without D's mass E[1 / cos theta_m] in the amplitudes (a few
// percent on such patches) it fails.
TEST(MultiLobeBrdf, LambertianBaseKeepsItsAlbedoThroughAFittedNdf) {
  const HeightField field = bumpyField(64, 9);
  const VmfMixture ndf = fitPatchNdf(patchMicroNormals(field, 16, 16, 32, 4), {});
  const MicrofacetBrdf lambert(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb::Zero(), Rgb(0.5, 0.7, 0.9));
  const MultiLobeBrdf rho(ndf, lambert);
  const Rgb value = rho.eval(Vec3(0, 0, 1), Vec3(0, 0, 1));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], lambert.diffuse()[c] / kPi, 0.005 * lambert.diffuse()[c] / kPi);
}

// Eq. (4.5) by brute force: D's lobes by 24 x 24 stratified vMF samples each.
Rgb rhoByQuadrature(const VmfMixture& ndf, const MicrofacetBrdf& base, const Vec3& wi, const Vec3& wo) {
  const int n = 24;
  Rgb sum = Rgb::Zero();
  for (const VmfLobe& lobe : ndf.lobes)
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const Frame frame = Frame::fromNormal(sampleVmf(lobe.kappa, lobe.mu, Point2((a + 0.5) / n, (b + 0.5) / n)));
        const double cos_i = frame.n.dot(wi);
        if (cos_i > 0) sum += base.eval(frame.toLocal(wo), frame.toLocal(wi)) * (cos_i * lobe.amplitude / (n * n));
      }
  return sum / wi.z();
}

// The closed form against Eq. (4.5) integrated over D for the fitted NDF of a bumpy patch, over
// light directions on 24 x 24 cosine-weighted strata: the reflectance under uniform light (the sum)
// agrees to 1%, and the shape (the L1 distance of the two over the sum) to 6% for a glossy base and
// 0.4% for a rough one. The negative control: the lobes' spread left out (the base roughness
// unwidened) gets the glossy shape far wrong.
TEST(MultiLobeBrdf, ClosedFormFollowsEq45OnAFittedNdf) {
  const HeightField field = bumpyField(64, 9);
  const VmfMixture ndf = fitPatchNdf(patchMicroNormals(field, 16, 16, 32, 4), {});
  VmfMixture unwidened = ndf;
  for (VmfLobe& lobe : unwidened.lobes) lobe.kappa = 1e9;
  for (double alpha : {0.1, 0.5}) {
    const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, alpha), Rgb::Constant(0.5), Rgb::Constant(0.2));
    const MultiLobeBrdf rho(ndf, base), narrow(unwidened, base);
    for (const Vec3& wo : {Vec3(0, 0, 1), Vec3(0.6, 0.3, 0.74).normalized()}) {
      double closed = 0, exact = 0, distance = 0, unwidened_distance = 0;
      const int n = 24;
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          const Vec3 wi = sampleCosineHemisphere(Point2((a + 0.5) / n, (b + 0.5) / n));
          const double c = rho.eval(wi, wo)[0], e = rhoByQuadrature(ndf, base, wi, wo)[0];
          closed += c;
          exact += e;
          distance += std::abs(c - e);
          unwidened_distance += std::abs(narrow.eval(wi, wo)[0] - e);
        }
      EXPECT_NEAR(closed / exact, 1, 0.01) << "alpha " << alpha << " wo " << wo.transpose();
      // Measured: L1 0.058 and 0.059 (alpha 0.1), 0.004 (alpha 0.5); unwidened 0.137, 0.139, 0.007, 0.006.
      EXPECT_LT(distance / exact, 0.08) << "alpha " << alpha << " wo " << wo.transpose();
      if (alpha == 0.1) EXPECT_GT(unwidened_distance / exact, 2 * distance / exact) << wo.transpose();
    }
  }
}

// sample() draws wi with the density pdf() (chi-square; samples below the macro-surface are
// absorbed and must match the missing mass), and its weight is eval cos theta_i / pdf.
TEST(MultiLobeBrdf, SamplingFollowsItsPdf) {
  const HeightField field = bumpyField(64, 9);
  const VmfMixture ndf = fitPatchNdf(patchMicroNormals(field, 16, 16, 32, 4), {});
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::Beckmann, 0.2), Rgb(0.9, 0.6, 0.3), Rgb(0.2, 0.3, 0.1));
  const MultiLobeBrdf rho(ndf, base);
  test::TestRandom random(4);
  std::uint64_t seed = 300;
  for (const Vec3& wo : {Vec3(0.1, 0, 1).normalized(), Vec3(0.7, 0.2, 0.5).normalized()}) {
    test::Chi2Options o;
    o.bins.frame = Frame::fromNormal(Vec3(0, 0, 1));
    o.test_count = 8;
    o.seed = ++seed;
    o.sample_count = 400'000;
    o.bins.tolerance = 1e-6;
    o.bins.max_depth = 5;
    o.absorbed_samples = true;
    const test::Chi2Result r = test::chi2TestBrdfSampling(
        [&](double u_lobe, const Point2& u) { return rho.sample(wo, u_lobe, u); },
        [&](const Vec3& wi) { return rho.pdf(wo, wi); }, o);
    EXPECT_TRUE(r.passed) << r.summary;
    for (int trial = 0; trial < 100; ++trial) {
      const double ul = random.uniform();
      const Point2 u = random.point2();
      const BrdfSample s = rho.sample(wo, ul, u);
      if (s.pdf == 0) continue;
      const Rgb expected = rho.eval(s.wi, wo) * s.wi.z() / rho.pdf(wo, s.wi);
      EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.maxCoeff()));
    }
  }
}

// MultiLobeBrdf::visibleMean: each lobe's own reflectance (the lobe alone, over its area) weighed
// by the area its facets show toward wo, for four lobes tilted up to 35 degrees, on the square tile and on a squeezed one, from views above
// and below the macro-surface's horizon; zero where no lobe faces wo. Eq. (4.5)'s sum over the total
// area, which weighs the lobes by area alone, is the negative control: below the horizon, where only
// some lobes face wo, it falls short of the mean of those that do.
TEST(MultiLobeBrdf, VisibleMeanWeighsEachLobeByTheAreaItShows) {
  const auto tilted = [](double theta_degrees, double phi_degrees) {
    const double theta = theta_degrees * kPi / 180, phi = phi_degrees * kPi / 180;
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  const VmfMixture ndf{{{0.4, 200, Vec3(0, 0, 1)}, {0.2, 80, tilted(25, 10)}, {0.2, 50, tilted(35, 200)}, {0.2, 100, tilted(20, 110)}}};
  const MicrofacetBrdf base(MicrofacetDistribution(MicrofacetKind::GGX, 0.3), Rgb(0.5, 0.4, 0.3), Rgb(0.3, 0.2, 0.1));
  const MultiLobeBrdf rho(ndf, base);
  const Vec3 wi = Vec3(0.2, -0.3, 0.9).normalized();
  double largest_shortfall = 0;
  for (const TileStretch& stretch : {TileStretch(), TileStretch::diagonal(0.5, 1)}) {
    for (const Vec3& wo : {Vec3(0.3, 0.1, 1).normalized(), Vec3(0.95, 0.2, -0.15).normalized(),
                           Vec3(-0.4, 0.9, -0.3).normalized()}) {
      Rgb seen = Rgb::Zero();
      double shown_area = 0, area = 0;
      for (const VmfLobe& lobe : ndf.lobes) {
        const MultiLobeBrdf alone(VmfMixture{{lobe}}, base);
        const double shown = std::max(0.0, stretch.normalOnSurface(lobe.mu).dot(wo));
        seen += alone.projected(wi, wo, stretch) * shown;
        shown_area += lobe.amplitude * stretch.facetWeight(lobe.mu) * shown;
        area += lobe.amplitude * stretch.facetWeight(lobe.mu);
      }
      ASSERT_GT(shown_area, 0) << wo.transpose();
      const Rgb expected = seen / shown_area, mean = rho.visibleMean(wi, wo, stretch);
      EXPECT_LT((mean - expected).abs().maxCoeff(), 1e-12 * expected.maxCoeff()) << wo.transpose();
      if (wo.z() < 0) largest_shortfall = std::max(largest_shortfall, 1 - rho.projected(wi, wo, stretch)[0] / area / mean[0]);
    }
    EXPECT_EQ(rho.visibleMean(wi, Vec3(0, 0, -1), stretch).maxCoeff(), 0);
  }
  EXPECT_GT(largest_shortfall, 0.3);  // measured 0.82
}

TEST(PatchNdf, RefusesAPatchOutsideTheField) {
  const HeightField field(8, 8, 0.1);
  EXPECT_THROW(patchMicroNormals(field, 4, 4, 8, 2), std::invalid_argument);
  EXPECT_THROW(fitVmfMixture({}, {}, {}), std::invalid_argument);
  EXPECT_THROW(fitVmfMixture({Vec3(0, 0, 1)}, {0.0}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace vdbappear
