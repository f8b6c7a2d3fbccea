// Image comparisons (vdb_image_compare): means, RMSE, masks, tile means and the error map.
#include "libvdbappear/image/image_compare.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vdbappear {
namespace {

RgbImage constantImage(int width, int height, float value) {
  RgbImage image(width, height);
  std::fill(image.pixels.begin(), image.pixels.end(), value);
  return image;
}

TEST(ImageCompare, MeansRmseAndMask) {
  RgbImage reference = constantImage(2, 1, 1.0f), test = constantImage(2, 1, 1.0f);
  for (int c = 0; c < 3; ++c) test.at(1, 0)[c] = 3.0f;  // pixel 1 off by 2 in every channel
  const ImageComparison all = compareImages(reference, test);
  EXPECT_DOUBLE_EQ(all.mean_reference, 1.0);
  EXPECT_DOUBLE_EQ(all.mean_test, 2.0);
  EXPECT_DOUBLE_EQ(all.mean_relative_error, 1.0);
  EXPECT_DOUBLE_EQ(all.rmse, std::sqrt(2.0));  // half the values off by 2
  EXPECT_DOUBLE_EQ(all.max_abs_error, 2.0);
  const ImageComparison first = compareImages(reference, test, {true, false});
  EXPECT_DOUBLE_EQ(first.rmse, 0.0);
  EXPECT_THROW(compareImages(reference, test, {false, false}), std::invalid_argument);
  EXPECT_THROW(compareImages(reference, constantImage(1, 2, 1.0f)), std::invalid_argument);
}

// The worst pixel's error is relative to the pixel where it is brighter than the image mean and to
// the mean where darker: a dim pixel off by a little does not dominate, a bright one off counts.
TEST(ImageCompare, WorstRelativeErrorIsRelativeToThePixelOrTheMean) {
  RgbImage reference = constantImage(4, 1, 0.0f), test = constantImage(4, 1, 0.0f);
  const float ref[4] = {4.0f, 0.01f, 2.0f, 2.0f}, got[4] = {4.4f, 0.11f, 2.0f, 1.9f};  // mean 2.0025
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) {
      reference.at(x, 0)[c] = ref[x];
      test.at(x, 0)[c] = got[x];
    }
  const ImageComparison c = compareImages(reference, test);
  EXPECT_NEAR(c.worst_relative_error, 0.4 / 4.0, 1e-6) << "the bright pixel, +10% of itself";
  EXPECT_NEAR(compareImages(reference, test, {false, true, true, true}).worst_relative_error, 0.1 / (4.01 / 3), 1e-6)
      << "the dim pixel, relative to the mean of the counted pixels";
  EXPECT_EQ(compareImages(reference, reference).worst_relative_error, 0.0);
}

TEST(ImageCompare, TileMeansAverageBlocksAndDropTheRemainder) {
  RgbImage image(5, 4);  // 2x2 tiles: 2 x 2 of them, column 4 dropped
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = float(x + 10 * y + 100 * c);
  const RgbImage tiles = tileMeans(image, 2);
  ASSERT_EQ(tiles.width, 2);
  ASSERT_EQ(tiles.height, 2);
  EXPECT_FLOAT_EQ(tiles.at(0, 0)[0], 5.5f);    // mean of 0, 1, 10, 11
  EXPECT_FLOAT_EQ(tiles.at(1, 1)[2], 227.5f);  // mean of 222, 223, 232, 233
  EXPECT_EQ(tileMeans(image, 1).pixels, image.pixels);
  EXPECT_THROW(tileMeans(image, 0), std::invalid_argument);
  EXPECT_THROW(tileMeans(image, 5), std::invalid_argument);  // taller than the image

  // A tile is foreground when more than half its pixels are.
  const std::vector<bool> mask{true, true, false, false, true,   // row 0
                               true, false, false, false, true,  // row 1
                               true, true, true, true, true,     // row 2
                               false, false, true, false, true}; // row 3
  EXPECT_EQ(tileMask(mask, 5, 4, 2), (std::vector<bool>{true, false, false, true}));
  EXPECT_TRUE(tileMask({}, 5, 4, 2).empty());
}

TEST(ImageCompare, ErrorMapIsRedWhereBrighterAndBlueWhereDarker) {
  RgbImage reference = constantImage(3, 1, 1.0f), test = constantImage(3, 1, 1.0f);
  for (int c = 0; c < 3; ++c) {
    test.at(0, 0)[c] = 2.0f;  // +100%
    test.at(2, 0)[c] = 0.0f;  // -100%
  }
  const RgbImage map = relativeErrorMap(reference, test, 0.5);
  EXPECT_FLOAT_EQ(map.at(0, 0)[0], 1.0f);
  EXPECT_FLOAT_EQ(map.at(0, 0)[2], 0.0f);
  EXPECT_FLOAT_EQ(map.at(1, 0)[1], 1.0f);  // equal: white
  EXPECT_FLOAT_EQ(map.at(2, 0)[0], 0.0f);
  EXPECT_FLOAT_EQ(map.at(2, 0)[2], 1.0f);
}

}  // namespace
}  // namespace vdbappear
