// Weave drafts: the defining properties of plain, twill and satin weaves.
#include "libvdbappear/procedural/weave_pattern.h"

#include <gtest/gtest.h>

namespace vdbappear {
namespace {

TEST(WeavePattern, PlainAlternatesAtEveryCrossing) {
  const WeavePattern p = WeavePattern::plain();
  for (int i = -3; i < 5; ++i)
    for (int j = -3; j < 5; ++j) {
      EXPECT_NE(p.warpOver(i, j), p.warpOver(i + 1, j));
      EXPECT_NE(p.warpOver(i, j), p.warpOver(i, j + 1));
    }
  EXPECT_DOUBLE_EQ(p.warpOverFraction(), 0.5);
}

TEST(WeavePattern, TwillFloatsStepByOneWeftPerWarp) {
  for (int n : {3, 4, 5, 8}) {
    const WeavePattern p = WeavePattern::twill(n);
    EXPECT_EQ(p.repeat(), n);
    EXPECT_DOUBLE_EQ(p.warpOverFraction(), double((n + 1) / 2) / n) << n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) EXPECT_EQ(p.warpOver(i, j), p.warpOver(i + 1, j + 1)) << "the wale, n = " << n;
  }
  EXPECT_THROW(WeavePattern::twill(2), std::invalid_argument);
}

TEST(WeavePattern, SatinInterlacesOncePerRepeatAndTheInterlacingsNeverTouch) {
  for (int n : {5, 7, 8, 12}) {
    const WeavePattern p = WeavePattern::satin(n);
    for (int i = 0; i < n; ++i) {
      int unders = 0, unders_in_column = 0;
      for (int j = 0; j < n; ++j) {
        unders += !p.warpOver(i, j);
        unders_in_column += !p.warpOver(j, i);
        if (!p.warpOver(i, j)) {  // no other interlacing among the 8 neighbours
          for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj)
              if (di || dj) EXPECT_TRUE(p.warpOver(i + di, j + dj)) << "n = " << n << " at " << i << "," << j;
        }
      }
      EXPECT_EQ(unders, 1);
      EXPECT_EQ(unders_in_column, 1);
    }
  }
  EXPECT_THROW(WeavePattern::satin(4), std::invalid_argument);
  EXPECT_THROW(WeavePattern::satin(6), std::invalid_argument) << "no counter in [2, 4] is coprime with 6";
}

TEST(WeavePattern, MirroredAndTransposedVariants) {
  const WeavePattern t = WeavePattern::twill(4), m = t.mirrored(), w = WeavePattern::twill(3).transposed();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(m.warpOver(i, j), m.warpOver(i + 1, j - 1)) << "the wale turns";
  EXPECT_DOUBLE_EQ(w.warpOverFraction(), 1.0 / 3.0) << "2/1 warp-faced becomes 1/2 weft-faced";
  EXPECT_THROW(WeavePattern::byName("jacquard"), std::invalid_argument);
  EXPECT_EQ(WeavePattern::byName("satin").repeat(), 5);
}

}  // namespace
}  // namespace vdbappear
