// Light sampling against its pdf (chi-square over directions), the lat-long convention, real
// spherical harmonics (orthonormality, the sign convention), and piecewise-constant sampling.
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/render/area_light.h"
#include "libvdbappear/render/environment_light.h"

#include "support/chi2_test.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <sstream>

namespace vdbappear {
namespace {

std::unique_ptr<EnvironmentLight> randomEnvironmentMap(int width, int height, std::uint64_t seed) {
  test::TestRandom random(seed);
  std::vector<float> rgb(std::size_t(width) * height * 3);
  for (float& v : rgb) v = float(random.uniform() < 0.3 ? 0.0 : std::pow(random.uniform(), 4) * 10);
  return EnvironmentLight::fromImage(width, height, rgb, 1.0);
}

TEST(EnvironmentLight, LatLongRoundTripAndBlenderConvention) {
  test::TestRandom random(2);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 w = random.direction();
    EXPECT_LT((EnvironmentLight::directionOf(EnvironmentLight::latLongOf(w)) - w).norm(), 1e-9);
  }
  EXPECT_LT((EnvironmentLight::directionOf(Point2(0.5, 0.5)) - Vec3(1, 0, 0)).norm(), 1e-12);  // centre: +x
  EXPECT_NEAR(EnvironmentLight::directionOf(Point2(0.3, 0.0)).z(), 1.0, 1e-12);                // top row: +z
  EXPECT_LT((EnvironmentLight::directionOf(Point2(0.25, 0.5)) - Vec3(0, 1, 0)).norm(), 1e-12); // left of centre: +y
}

TEST(EnvironmentLight, MapSamplingFollowsItsPdf) {
  const auto light = randomEnvironmentMap(16, 8, 4);
  const test::Chi2Result r = test::chi2TestDirections([&](const Point2& u) { return light->sample(Vec3::Zero(), u).wi; },
                                                      [&](const Vec3& w) { return light->pdf(Vec3::Zero(), w); }, {});
  EXPECT_TRUE(r.passed) << r.summary;
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
}

// Sample-versus-pdf consistency by Monte Carlo: for directions drawn by sample(), the mean of
// g(w) / pdf(w) must be the integral of g, for the indicator of each octant (area pi/2) and for
// Y_lm^2 (integral 1). A pdf that disagrees with the sampler anywhere biases one of them.
// (The chi-square test needs smooth pdfs to integrate; these tabulated ones are piecewise.)
// The mean of estimate(u) over 200000 uniform u must equal `integral` within 5 standard errors.
void expectMeanIs(const std::function<double(const Point2&)>& estimate, double integral, const std::string& what) {
  RandomStream rng(7, {int(what.size())});
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double v = estimate(rng.uniform2());
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, integral, 5 * error + 1e-12) << what;
}

template <typename SampleFn, typename PdfFn>
void expectConsistent(SampleFn&& sample, PdfFn&& pdf, const std::function<double(const Vec3&)>& g, double integral,
                      const std::string& what) {
  expectMeanIs([&](const Point2& u) {
    const Vec3 w = sample(u);
    const double p = pdf(w);
    return p > 0 ? g(w) / p : 0.0;
  }, integral, what);
}

TEST(EnvironmentLight, SphericalHarmonicSamplingMatchesItsPdfAndKeepsTheSign) {
  for (const std::pair<int, int> lm : {std::pair{0, 0}, {1, -1}, {2, 1}, {3, -2}}) {
    const int l = lm.first, m = lm.second;  // lambdas cannot capture bindings (C++17)
    const auto light = EnvironmentLight::sphericalHarmonic(l, m, 1.0);
    const auto sample = [&](const Point2& u) { return light->sample(Vec3::Zero(), u).wi; };
    const auto pdf = [&](const Vec3& w) { return light->pdf(Vec3::Zero(), w); };
    const std::string name = "Y_" + std::to_string(l) + "," + std::to_string(m);
    for (int octant = 0; octant < 8; ++octant) {
      const auto inside = [octant](const Vec3& w) {
        return double((w.x() > 0) == bool(octant & 1) && (w.y() > 0) == bool(octant & 2) && (w.z() > 0) == bool(octant & 4));
      };
      expectConsistent(sample, pdf, inside, kPi / 2, name + " octant " + std::to_string(octant));
    }
    expectConsistent(sample, pdf, [&](const Vec3& w) { return std::pow(sphericalHarmonic(l, m, w), 2); }, 1.0, name + " norm");
    const Vec3 w = Vec3(0.3, -0.6, 0.2).normalized();
    EXPECT_DOUBLE_EQ(light->radiance(w)[0], sphericalHarmonic(l, m, w));
  }
}

// Smoothness (LightStrategy::kAuto leaves smooth lights to phase sampling): the peak over the
// mean of |radiance| over the sphere, in closed form for a constant sky (1), |Y_1m| (2) and |Y_20|
// (2 / (4 / (3 sqrt 3)) = 2.60); a sky of 1 with a sun 500 times brighter in one of 64x32 cells is not
// smooth.
TEST(EnvironmentLight, SmoothnessIsThePeakOverTheMean) {
  EXPECT_DOUBLE_EQ(EnvironmentLight::constant(Rgb::Constant(0.3))->peakToMean(), 1.0);
  EXPECT_TRUE(EnvironmentLight::constant(Rgb::Constant(0.3))->isSmooth());
  for (const int m : {-1, 0, 1}) {
    const auto band1 = EnvironmentLight::sphericalHarmonic(1, m, 2.0);
    EXPECT_NEAR(band1->peakToMean(), 2.0, 0.02) << "m = " << m;
    EXPECT_TRUE(band1->isSmooth());
  }
  EXPECT_NEAR(EnvironmentLight::sphericalHarmonic(2, 0, 1.0)->peakToMean(), 3 * std::sqrt(3.0) / 2, 0.03);
  const int width = 64, height = 32;
  std::vector<float> rgb(std::size_t(width) * height * 3, 1.0f);
  for (int c = 0; c < 3; ++c) rgb[(std::size_t(8) * width + 20) * 3 + c] = 500.0f;
  const auto sunny = EnvironmentLight::fromImage(width, height, rgb, 1.0);
  EXPECT_GT(sunny->peakToMean(), 100.0);
  EXPECT_FALSE(sunny->isSmooth());
}

TEST(SphericalHarmonics, OrthonormalAndConventional) {
  // Midpoint rule in (cos theta, phi): exact in phi, O(1/n^2) in cos theta for these polynomials.
  const int lmax = 4, count = shCount(lmax), n_z = 2000, n_phi = 64;
  std::vector<double> gram(count * count, 0.0);
  for (int i = 0; i < n_z; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const double z = -1 + (2.0 * i + 1) / n_z, phi = 2 * kPi * (j + 0.5) / n_phi, r = std::sqrt(1 - z * z);
      const auto Y = evalSphericalHarmonics(lmax, Vec3(r * std::cos(phi), r * std::sin(phi), z));
      for (int a = 0; a < count; ++a)
        for (int b = 0; b < count; ++b) gram[a * count + b] += Y[a] * Y[b] * (2.0 / n_z) * (2 * kPi / n_phi);
    }
  for (int a = 0; a < count; ++a)
    for (int b = 0; b < count; ++b) EXPECT_NEAR(gram[a * count + b], a == b ? 1.0 : 0.0, 1e-4) << a << "," << b;
  const Vec3 w = Vec3(0.48, -0.6, 0.64);
  const double c = std::sqrt(3 / (4 * kPi));
  EXPECT_NEAR(sphericalHarmonic(1, -1, w), -c * w.y(), 1e-12);  // Condon-Shortley phase
  EXPECT_NEAR(sphericalHarmonic(1, 0, w), c * w.z(), 1e-12);
  EXPECT_NEAR(sphericalHarmonic(1, 1, w), -c * w.x(), 1e-12);
  EXPECT_NEAR(sphericalHarmonic(0, 0, w), 0.5 / std::sqrt(kPi), 1e-12);
}

// Solid angle of a triangle seen from p (Van Oosterom and Strackee 1983).
double solidAngle(const Triangle& t, const Vec3& p) {
  const Vec3 a = t[0] - p, b = t[1] - p, c = t[2] - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = std::abs(a.dot(b.cross(c)));
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2 * std::atan2(numerator, denominator);
}

TEST(AreaLight, SamplingMatchesItsSolidAnglePdf) {
  // A non-planar quad (two triangles of different areas) seen from two points.
  const std::vector<Vec3> quad{{-1, -1, 2}, {1, -1, 2}, {1.5, 1, 2.5}, {-1, 1, 2}};
  const AreaLight light(AreaLight::fanTriangulate(quad), Rgb::Ones(), true);
  for (const Vec3& p : {Vec3(0.2, 0.1, 0), Vec3(-3, 0.5, 1.9)}) {
    double omega = 0;
    for (const Triangle& t : light.triangles()) omega += solidAngle(t, p);
    // E[1 / pdf] over light samples = the solid angle the light covers (a sample without pdf: NaN, a failure).
    std::ostringstream from;
    from << "from " << p.transpose();
    expectMeanIs([&](const Point2& u) {
      const LightSample s = light.sample(p, u);
      return s.pdf > 0 ? 1 / s.pdf : std::nan("");
    }, omega, from.str());
  }
}

TEST(AreaLight, OneSidedEmitsTowardItsCounterClockwiseNormal) {
  const AreaLight light(AreaLight::fanTriangulate({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}), Rgb::Ones(), false);
  EXPECT_GT(light.sample(Vec3(0.2, 0.2, 2), Point2(0.3, 0.3)).Li[0], 0);  // above: the normal is +z
  EXPECT_EQ(light.sample(Vec3(0.2, 0.2, 0), Point2(0.3, 0.3)).Li[0], 0);
}

}  // namespace
}  // namespace vdbappear
