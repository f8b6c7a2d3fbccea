// Chi-square tests of SGGX sampling against its pdf (Mitsuba 3's practice): the specular
// microflake phase function (wo) and the distribution of visible normals (m).
#include "libvdbappear/math/sggx.h"

#include "support/chi2_test.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <string>

namespace vdbappear {
namespace {

struct SamplingCase {
  std::string name;
  Mat3 S;
  Vec3 wi;
};

std::vector<SamplingCase> samplingCases() {
  test::TestRandom random(11);
  std::vector<SamplingCase> cases;
  cases.push_back({"isotropic", Mat3::Identity(), random.direction()});
  for (int k = 0; k < 10; ++k)
    cases.push_back({"random_" + std::to_string(k), random.spd(0.05), random.direction()});
  for (int k = 0; k < 5; ++k)
    cases.push_back({"random_stiff_" + std::to_string(k), random.spd(1e-3), random.direction()});
  for (double r : {0.5, 0.2, 0.05, 0.02}) {
    const std::string suffix = std::to_string(int(r * 100));
    cases.push_back({"fiber_r" + suffix, Sggx::fiberMatrix(random.direction(), r), random.direction()});
    cases.push_back({"flake_r" + suffix, Sggx::surfaceMatrix(random.direction(), r), random.direction()});
  }
  // Grazing and head-on incidence on a near-degenerate fiber and flake.
  const Vec3 t(0, 0, 1);
  cases.push_back({"fiber_r5_along", Sggx::fiberMatrix(t, 0.05), Vec3(0.05, 0, 1).normalized()});
  cases.push_back({"fiber_r5_across", Sggx::fiberMatrix(t, 0.05), Vec3(1, 0, 0)});
  cases.push_back({"flake_r5_grazing", Sggx::surfaceMatrix(t, 0.05), Vec3(1, 0, 0.05).normalized()});
  return cases;
}

const std::vector<SamplingCase>& cases() {
  static const std::vector<SamplingCase> all = samplingCases();
  return all;
}

class SggxSampling : public testing::TestWithParam<std::size_t> {
 protected:
  // Bins about wi: the visible-normal pdf's kink (m . wi = 0) then falls on a bin boundary.
  test::Chi2Options options() const {
    test::Chi2Options o;
    o.bins.frame = Frame::fromNormal(cases()[GetParam()].wi);
    o.test_count = int(2 * cases().size());  // Sidak correction over the whole suite
    o.seed = 1000 + GetParam();
    return o;
  }
};

TEST_P(SggxSampling, PhaseSamplesFollowThePhaseFunction) {
  const SamplingCase& c = cases()[GetParam()];
  const Sggx sggx(c.S);
  const test::Chi2Result r = test::chi2TestDirections([&](const Point2& u) { return sggx.samplePhase(c.wi, u).wo; },
                                                      [&](const Vec3& wo) { return sggx.phase(c.wi, wo); }, options());
  EXPECT_TRUE(r.passed) << c.name << ": " << r.summary;
  EXPECT_GE(r.degrees_of_freedom, 100) << "too few populated bins to have power: " << r.summary;
  RecordProperty("chi2", r.summary);
}

TEST_P(SggxSampling, VisibleNormalSamplesFollowTheVisibleNormalDistribution) {
  const SamplingCase& c = cases()[GetParam()];
  const Sggx sggx(c.S);
  const test::Chi2Result r =
      test::chi2TestDirections([&](const Point2& u) { return sggx.sampleVisibleNormal(c.wi, u); },
                               [&](const Vec3& m) { return sggx.visibleNormalPdf(c.wi, m); }, options());
  EXPECT_TRUE(r.passed) << c.name << ": " << r.summary;
  EXPECT_GE(r.degrees_of_freedom, 100) << "too few populated bins to have power: " << r.summary;
  RecordProperty("chi2", r.summary);
}

INSTANTIATE_TEST_SUITE_P(Cases, SggxSampling, testing::Range<std::size_t>(0, cases().size()),
                         [](const testing::TestParamInfo<std::size_t>& info) { return cases()[info.param].name; });

// The test must be able to fail: a sampler with a subtly wrong distribution (roughness off by 5%)
// is rejected.
TEST(SggxSamplingPower, RejectsASlightlyWrongSampler) {
  const Vec3 t = Vec3(0.3, -0.5, 0.8).normalized(), wi = Vec3(0.9, 0.1, -0.2).normalized();
  const Sggx truth = Sggx::fromFiberTangent(t, 0.3), wrong = Sggx::fromFiberTangent(t, 0.315);
  const test::Chi2Result r = test::chi2TestDirections([&](const Point2& u) { return wrong.samplePhase(wi, u).wo; },
                                                      [&](const Vec3& wo) { return truth.phase(wi, wo); }, {});
  EXPECT_FALSE(r.passed) << r.summary;
}

}  // namespace
}  // namespace vdbappear
