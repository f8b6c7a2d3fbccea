// The procedural displacement maps (libvdbappear/procedural/height_maps.h): each tiles (opposite
// edges match), the noise floor has its stated RMS slope and follows its seed, the twill's warp
// yarns lie as the weave's draft says, and unknown names are refused.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/procedural/height_maps.h"
#include "libvdbappear/procedural/weave_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {
namespace {

double rmsSlope(const HeightField& f) {
  double sum = 0;
  for (int j = 0; j < f.cellsY(); ++j)
    for (int i = 0; i < f.cellsX(); ++i) sum += f.cellSlope(i, j).squaredNorm();
  return std::sqrt(sum / (double(f.cellsX()) * f.cellsY()));
}

TEST(HeightMaps, EveryKindTiles) {
  for (const std::string& name : heightMapNames()) {
    const HeightField f = heightMapByName(name, 128, 3);
    EXPECT_NEAR(f.cellSize(), 1.0 / 128, 1e-15);
    double scale = 0;
    for (double h : f.heights()) scale = std::max(scale, std::abs(h));
    ASSERT_GT(scale, 0) << name;
    for (int k = 0; k <= 128; ++k) {
      EXPECT_NEAR(f.at(0, k), f.at(128, k), 1e-9 * scale) << name << " row " << k;
      EXPECT_NEAR(f.at(k, 0), f.at(k, 128), 1e-9 * scale) << name << " column " << k;
    }
  }
  EXPECT_THROW(heightMapByName("marble", 64, 1), std::invalid_argument);
  EXPECT_THROW(heightMapByName("woven", 100, 1), std::invalid_argument);  // not a multiple of the 16 yarns
}

TEST(HeightMaps, NoiseFloorHasItsSlopeAndFollowsItsSeed) {
  const HeightField a = noiseHeightMap(512, 7), b = noiseHeightMap(512, 7), c = noiseHeightMap(512, 8);
  EXPECT_EQ(a.heights(), b.heights());
  EXPECT_NE(a.heights(), c.heights());
  EXPECT_NEAR(rmsSlope(a), 0.6, 0.03);  // the sum's mean |grad|^2, sampled on the grid
}

// At each crossing the yarn on top shows its cross-section: where the draft puts the warp (along y)
// over the weft, the surface falls faster across x than across y, and the other way round where the
// weft is on top; half the crossings of the 4-harness twill each.
TEST(HeightMaps, TwillYarnsLieAsTheDraftSays) {
  const WeavePattern twill = WeavePattern::twill(4);
  const int cells = 256, yarns = 16, per_yarn = cells / yarns, quarter = per_yarn / 4;
  const HeightField f = wovenHeightMap(cells, twill, yarns);
  int warp_on_top = 0;
  for (int weft = 0; weft < yarns; ++weft)
    for (int warp = 0; warp < yarns; ++warp) {
      const int x = warp * per_yarn + per_yarn / 2, y = weft * per_yarn + per_yarn / 2;
      const double fall_across_x = f.at(x, y) - f.at(x + quarter, y), fall_across_y = f.at(x, y) - f.at(x, y + quarter);
      EXPECT_EQ(fall_across_x > fall_across_y, twill.warpOver(warp, weft)) << warp << ", " << weft;
      warp_on_top += twill.warpOver(warp, weft);
    }
  EXPECT_EQ(warp_on_top, yarns * yarns / 2);
}

// Bumps are caps inside their lattice cells: none below zero, none above the tallest cap
// (0.6 x 0.45 cells), zero along the lattice lines (so the map tiles whatever the seed), and caps
// cover between pi 0.3^2 and pi 0.45^2 of the map.
TEST(HeightMaps, BumpsAreCapsInsideTheirCells) {
  const int cells = 256;
  const HeightField f = bumpsHeightMap(cells, 11);
  double peak = 0, covered = 0;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const double h = f.at(i, j);
      EXPECT_GE(h, 0);
      peak = std::max(peak, h);
      if (i < cells && j < cells) covered += h > 0;
      if (i % (cells / 8) == 0 || j % (cells / 8) == 0) EXPECT_EQ(h, 0) << i << " " << j;
    }
  EXPECT_LE(peak, 0.6 * 0.45 / 8 + 1e-12);
  EXPECT_GT(peak, 0.6 * 0.3 / 8);
  covered /= double(cells) * cells;
  EXPECT_GT(covered, kPi * 0.3 * 0.3);
  EXPECT_LT(covered, kPi * 0.45 * 0.45);
  EXPECT_NE(bumpsHeightMap(cells, 12).heights(), f.heights());
}

}  // namespace
}  // namespace vdbappear
