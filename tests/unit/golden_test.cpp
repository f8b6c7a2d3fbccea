// Golden grids (grids/golden/): results that must not change unless a commit says why. The
// generators' golden media are checked by tests/cli/golden_media_test.cpp.
// Tolerance 1e-6 absolute on every value (values are O(1) to O(50); float rounding is ~1e-7 relative).
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/medium.h"

#include "support/medium_testing.h"

#include <gtest/gtest.h>

namespace vdbappear {
namespace {

constexpr double kTolerance = 1e-6;

void expectMediaMatch(const Medium& expected, const Medium& actual) {
  EXPECT_EQ(actual.transform(), expected.transform());
  EXPECT_TRUE(test::gridsMatch(*expected.density, *actual.density, kTolerance * 50));
  EXPECT_TRUE(test::gridsMatch(*expected.albedo, *actual.albedo, kTolerance));
  EXPECT_TRUE(test::gridsMatch(*expected.sggx_diag, *actual.sggx_diag, kTolerance));
  EXPECT_TRUE(test::gridsMatch(*expected.sggx_offdiag, *actual.sggx_offdiag, kTolerance));
}

TEST(Golden, NaiveDownsamplingReproducesItsGoldenGrid) {
  const MediumPtr input = readMedium(GOLDEN_DIR "/twill24.vdb");
  const MediumPtr golden = readMedium(GOLDEN_DIR "/twill24_naive2x.vdb");
  expectMediaMatch(*golden, *downsampleNaive(*input, {2, SggxWeighting::Count}).medium);
}

}  // namespace
}  // namespace vdbappear
