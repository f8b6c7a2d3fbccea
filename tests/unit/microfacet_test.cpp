// The base micro-BRDFs of the displacement chapter (libvdbappear/surface/microfacet_*.h): the
// normalisation of D (Eq. 4.3), Smith's projected-area identity (the single-direction form of
// Eq. 4.8, which is also the weak white furnace), reciprocity, energy lost only to shadowing,
// chi-square tests of every sampler against its pdf, with the negative control that a slightly
// wrong roughness is rejected, and the lobe choice that lowers the weights' variance at grazing
// views.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/surface/microfacet_brdf.h"

#include "support/brdf_chi2.h"
#include "support/chi2_test.h"
#include "support/sphere_quadrature.h"
#include "support/test_random.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

namespace vdbappear {
namespace {

struct Case {
  MicrofacetKind kind;
  double alpha;
};

const Case kCases[] = {{MicrofacetKind::GGX, 0.05},     {MicrofacetKind::GGX, 0.3},
                       {MicrofacetKind::GGX, 1.0},      {MicrofacetKind::Beckmann, 0.05},
                       {MicrofacetKind::Beckmann, 0.3}, {MicrofacetKind::Beckmann, 1.0}};

std::string name(const Case& c) { return std::string(microfacetKindName(c.kind)) + " alpha " + std::to_string(c.alpha); }

// int_0^1 f(mu) dmu by adaptive Gauss-Kronrod (narrow lobes and kinks are resolved by bisection).
double integrateUnit(const std::function<double(double)>& f) {
  return boost::math::quadrature::gauss_kronrod<double, 15>::integrate(f, 0.0, 1.0, 20, 1e-11);
}

Vec3 fromCosTheta(double cos_theta) { return test::sphericalDirection(Frame::fromNormal(Vec3(0, 0, 1)), cos_theta, 0); }

// int_0^{2 pi} max(0, a cos phi + b) dphi, a >= 0: the azimuthal integral of a clamped cosine.
double clampedCosineOverPhi(double a, double b) {
  if (b >= a) return 2 * kPi * b;
  if (b <= -a) return 0;
  const double phi_c = std::acos(-b / a);
  return 2 * (a * std::sin(phi_c) + b * phi_c);
}

// Isotropic D makes the integrals over m one-dimensional in mu = cos theta_m.
TEST(Microfacet, NormalDistributionHasUnitProjectedArea) {  // Eq. (4.3)
  for (const Case& c : kCases) {
    const MicrofacetDistribution d(c.kind, c.alpha);
    const double integral = 2 * kPi * integrateUnit([&](double mu) { return d.D(fromCosTheta(mu)) * mu; });
    EXPECT_NEAR(integral, 1, 1e-8) << name(c);
  }
}

// Smith's masking makes the visible projected area of the micro-normals equal that of the macro
// surface: int G1(wo) <wo, m> D(m) dm = cos theta_o for every wo. After the change of variables
// m -> wi = reflect(wo, m) (dwi = 4 <wo, m> dm) this is also the weak white furnace (Heitz 2014,
// §4.2): with F = 1 and G1(wo) in place of G2 the specular lobe reflects all the light.
TEST(Microfacet, SmithMaskingConservesTheProjectedArea) {
  for (const Case& c : kCases) {
    const MicrofacetDistribution d(c.kind, c.alpha);
    for (double cos_o : {1.0, 0.7, 0.3, 0.08}) {
      const double sin_o = std::sqrt(1 - cos_o * cos_o);
      const Vec3 wo(sin_o, 0, cos_o);
      const double area = d.G1(wo) * integrateUnit([&](double mu) {
        const double sin_m = std::sqrt(std::max(0.0, 1 - mu * mu));
        return d.D(fromCosTheta(mu)) * clampedCosineOverPhi(sin_o * sin_m, cos_o * mu);
      });
      EXPECT_NEAR(area, cos_o, 1e-7) << name(c) << ", cos theta_o " << cos_o;
    }
  }
}

TEST(Microfacet, BrdfIsReciprocal) {
  test::TestRandom random(5);
  const MicrofacetBrdf brdf(MicrofacetDistribution(MicrofacetKind::GGX, 0.4), Rgb(1, 0.8, 0.5), Rgb(0.1, 0.2, 0.3));
  for (int trial = 0; trial < 200; ++trial) {
    Vec3 wo = random.direction(), wi = random.direction();
    wo.z() = std::abs(wo.z());
    wi.z() = std::abs(wi.z());
    // Schlick's F(<wo, h>) = F(<wi, h>): the half vector makes the same angle with both.
    EXPECT_LT((brdf.eval(wo, wi) - brdf.eval(wi, wo)).abs().maxCoeff(), 1e-12);
  }
}

// F = 1, no diffuse, GGX's visible normals: each sample's weight is G2(wo, wi) / G1(wo), in [0, 1]:
// what the lobe loses is shadowed light and reflections below the horizon (single scattering).
TEST(Microfacet, SpecularLobeLosesEnergyOnlyToShadowing) {
  const MicrofacetBrdf mirror(MicrofacetDistribution(MicrofacetKind::GGX, 0.5), Rgb::Ones(), Rgb::Zero());
  test::TestRandom random(8);
  for (double cos_o : {0.9, 0.5, 0.2}) {
    const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);
    double sum = 0;
    const int n = 100000;
    for (int k = 0; k < n; ++k) {
      const BrdfSample s = mirror.sample(wo, random.uniform(), random.point2());
      ASSERT_GE(s.weight[0], 0);
      ASSERT_LE(s.weight[0], 1 + 1e-12);
      if (s.pdf > 0) EXPECT_NEAR(s.weight[0], mirror.distribution().G2(wo, s.wi) / mirror.distribution().G1(wo), 1e-9);
      sum += s.weight[0];
    }
    EXPECT_LT(sum / n, 1) << "cos theta_o " << cos_o;
  }
}

test::Chi2Options hemisphereOptions(const Vec3& axis, std::uint64_t seed) {
  test::Chi2Options o;
  o.bins.frame = Frame::fromNormal(axis);
  o.test_count = 24;
  o.seed = seed;
  o.sample_count = 400'000;
  o.bins.tolerance = 1e-6;  // expected counts to 1e-6 of themselves; the clamped cosines kink
  o.bins.max_depth = 5;
  return o;
}

test::Chi2Options absorbing(test::Chi2Options o) {
  o.absorbed_samples = true;  // reflections below the horizon
  return o;
}

TEST(Microfacet, NormalSamplingFollowsItsPdf) {
  std::uint64_t seed = 100;
  for (const Case& c : kCases) {
    const MicrofacetDistribution d(c.kind, c.alpha);
    for (double cos_o : {0.9, 0.3}) {
      const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);
      const test::Chi2Result r = test::chi2TestDirections(
          [&](const Point2& u) { return d.sampleNormal(wo, u); }, [&](const Vec3& m) { return d.normalPdf(wo, m); },
          hemisphereOptions(Vec3(0, 0, 1), ++seed));
      EXPECT_TRUE(r.passed) << name(c) << ", cos theta_o " << cos_o << ": " << r.summary;
      EXPECT_NEAR(r.pdf_integral, 1, 1e-3) << name(c);
    }
  }
}

TEST(Microfacet, BrdfSamplingFollowsItsPdfAndWeightsAreEvalOverPdf) {
  std::uint64_t seed = 200;
  test::TestRandom random(9);
  for (const Case& c : kCases) {
    const MicrofacetBrdf brdf(MicrofacetDistribution(c.kind, c.alpha), Rgb(0.9, 0.6, 0.3), Rgb(0.2, 0.3, 0.1));
    // A view where the lobes are drawn about as at normal incidence, and a grazing one, where
    // Fresnel and masking move the choice (specularProbability).
    for (const Vec3& wo : {Vec3(0.6, 0.2, 0.5).normalized(), Vec3(0.95, 0.1, 0.12).normalized()}) {
      const test::Chi2Result r = test::chi2TestBrdfSampling(
          [&](double u_lobe, const Point2& u) { return brdf.sample(wo, u_lobe, u); },
          [&](const Vec3& wi) { return brdf.pdf(wo, wi); }, absorbing(hemisphereOptions(reflect(wo, Vec3(0, 0, 1)), ++seed)));
      EXPECT_TRUE(r.passed) << name(c) << ", cos theta_o " << wo.z() << ": " << r.summary;
      for (int trial = 0; trial < 100; ++trial) {
        const BrdfSample s = brdf.sample(wo, random.uniform(), random.point2());
        if (s.pdf == 0) continue;
        const Rgb expected = brdf.eval(wo, s.wi) * s.wi.z() / brdf.pdf(wo, s.wi);
        EXPECT_LT((s.weight - expected).abs().maxCoeff(), 1e-9 * (1 + expected.maxCoeff()));
      }
    }
  }
}

// The relative variance of a sampler's weights (their mean over the channels) for wo: the noise per
// path under a uniform sky, which such a surface's BRDF draws alone carry.
double weightRelativeVariance(const Vec3& wo, const std::function<BrdfSample(double, const Point2&)>& sample) {
  test::TestRandom random(31);
  double sum = 0, sum2 = 0;
  const int n = 200'000;
  for (int i = 0; i < n; ++i) {
    const double w = sample(random.uniform(), random.point2()).weight.mean();
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / n;
  return (sum2 / n - mean * mean) / (mean * mean);
}

// The lobe choice: F0 / (F0 + diffuse) at normal incidence, and toward a grazing view Schlick's
// Fresnel times G1 there, several times higher, which lowers the weights' variance. Negative
// control: the former fixed choice, at its normal-incidence value, by the same draws.
TEST(Microfacet, LobeChoiceFollowsFresnelAndMaskingAtTheView) {
  const MicrofacetDistribution ggx(MicrofacetKind::GGX, 0.3);
  const Rgb f0(0.04, 0.04, 0.04), diffuse(0.7, 0.55, 0.4);
  const MicrofacetBrdf brdf(ggx, f0, diffuse);
  const double at_normal = 0.04 / (0.04 + average(diffuse));
  EXPECT_NEAR(brdf.specularProbability(1), at_normal, 1e-12);
  for (double cos_o : {0.8, 0.5, 0.3, 0.15, 0.08}) {
    const double p = brdf.specularProbability(cos_o);
    const double s = average(schlickFresnel(f0, cos_o)) * ggx.G1(fromCosTheta(cos_o));
    EXPECT_NEAR(p, s / (s + average(diffuse)), 1e-12) << "cos theta_o " << cos_o;
    if (cos_o <= 0.3) EXPECT_GT(p, 2 * at_normal) << "cos theta_o " << cos_o;
  }
  EXPECT_EQ(brdf.specularProbability(0), 0);  // G1 is 0 on the horizon
  EXPECT_EQ(MicrofacetBrdf(ggx, Rgb::Zero(), Rgb::Zero()).specularProbability(0.5), 1);  // no diffuse lobe
  EXPECT_EQ(MicrofacetBrdf(ggx, Rgb::Zero(), Rgb::Zero()).specularProbability(1), 1);    // no lobe at all

  // The specular lobe's visible normals reflected, density normalPdf / (4 <wo, h>) (Walter et al.
  // 2007, Eq. 14), or the cosine-weighted diffuse lobe.
  const auto fixed_choice = [&](const Vec3& wo, double u_lobe, const Point2& u) {
    const Vec3 wi = u_lobe < at_normal ? reflect(wo, ggx.sampleNormal(wo, u)) : sampleCosineHemisphere(u);
    const Vec3 h = (wo + wi).normalized();
    const double specular_pdf = ggx.normalPdf(wo, h) / (4 * wo.dot(h));
    const double pdf = at_normal * specular_pdf + (1 - at_normal) * cosineHemispherePdf(wi.z());
    BrdfSample s;
    if (wi.z() > 0 && pdf > 0) s = {wi, brdf.eval(wo, wi) * (wi.z() / pdf), pdf};
    return s;
  };
  for (double cos_o : {0.2, 0.1}) {
    const Vec3 wo = fromCosTheta(cos_o);
    const double now = weightRelativeVariance(wo, [&](double ul, const Point2& u) { return brdf.sample(wo, ul, u); });
    const double fixed = weightRelativeVariance(wo, [&](double ul, const Point2& u) { return fixed_choice(wo, ul, u); });
    EXPECT_LT(now, 0.7 * fixed) << "cos theta_o " << cos_o << ": " << now << " against " << fixed;
  }
}

TEST(Microfacet, ChiSquareRejectsASlightlyWrongRoughness) {  // the negative control
  for (MicrofacetKind kind : {MicrofacetKind::GGX, MicrofacetKind::Beckmann}) {
    const MicrofacetDistribution sampled(kind, 0.3 * 1.05), evaluated(kind, 0.3);
    const Vec3 wo = Vec3(0.5, 0, 0.8).normalized();
    const test::Chi2Result r = test::chi2TestDirections(
        [&](const Point2& u) { return sampled.sampleNormal(wo, u); },
        [&](const Vec3& m) { return evaluated.normalPdf(wo, m); }, hemisphereOptions(Vec3(0, 0, 1), 7));
    EXPECT_FALSE(r.passed) << microfacetKindName(kind) << ": " << r.summary;
  }
}

TEST(Microfacet, RefusesBadParameters) {
  EXPECT_THROW(MicrofacetDistribution(MicrofacetKind::GGX, 0), std::invalid_argument);
  EXPECT_THROW(MicrofacetDistribution(MicrofacetKind::Beckmann, -0.1), std::invalid_argument);
  EXPECT_THROW(MicrofacetDistribution(MicrofacetKind::GGX, std::nan("")), std::invalid_argument);
  EXPECT_THROW(parseMicrofacetKind("phong"), std::invalid_argument);
  const MicrofacetDistribution d(MicrofacetKind::GGX, 0.2);
  EXPECT_THROW(MicrofacetBrdf(d, Rgb(1.2, 0, 0), Rgb::Zero()), std::invalid_argument);
  EXPECT_THROW(MicrofacetBrdf(d, Rgb::Zero(), Rgb(-0.1, 0, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace vdbappear
