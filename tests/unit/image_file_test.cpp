// image/image_file.h: OpenEXR files through OpenEXR (channel order, half and float pixels, data
// windows away from the origin, damaged files) and other formats through the OpenImageIO module.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/util/error.h"

#include "support/temp_dir.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vdbappear {
namespace {

using test::TempDir;

float valueAt(std::size_t pixel, std::size_t channel) { return 0.25f * float(pixel) + 100.0f * float(channel) + 0.125f; }

// A 5x3 image (not square, so that a swapped stride shows) with channels in a scrambled order.
ImageChannels scrambledChannels() {
  ImageChannels image;
  image.width = 5;
  image.height = 3;
  image.names = {"variance.R", "B", "cluster.0", "A", "G", "R", "variance.G", "variance.B"};
  for (std::size_t i = 0; i < 15; ++i)
    for (std::size_t c = 0; c < image.names.size(); ++c) image.values.push_back(valueAt(i, c));
  return image;
}

std::string errorOf(const std::string& path) {
  try {
    readImageChannels(path);
  } catch (const MediumError& e) {
    return e.what();
  }
  return "accepted";
}

// R, G, B, A first within a layer, unlayered channels first (OpenImageIO's order, which rgbOf and
// the tests of the renderer's AOVs rely on); every value where it was written.
TEST(ImageFile, ExrChannelsComeBackInOpenImageIOsOrder) {
  const TempDir dir;
  const ImageChannels written = scrambledChannels();
  writeExr(written, dir.path("a.exr"));
  const ImageChannels read = readImageChannels(dir.path("a.exr"));
  ASSERT_EQ(read.names, (std::vector<std::string>{"R", "G", "B", "A", "cluster.0", "variance.R", "variance.G",
                                                  "variance.B"}));
  ASSERT_EQ(read.width, 5);
  ASSERT_EQ(read.height, 3);
  for (std::size_t c = 0; c < read.names.size(); ++c) {
    const int w = written.find(read.names[c]);
    for (std::size_t i = 0; i < 15; ++i) EXPECT_EQ(read.values[i * 8 + c], valueAt(i, w)) << read.names[c] << " " << i;
  }
  const RgbImage rgb = rgbOf(read);
  EXPECT_EQ(rgb.at(4, 2)[0], valueAt(14, 5));  // R of the last pixel
}

// writeImage keeps EXR colour in half precision: each value within half's rounding (2^-11).
TEST(ImageFile, RgbExrIsHalfPrecision) {
  const TempDir dir;
  RgbImage image(4, 2);
  for (std::size_t k = 0; k < image.pixels.size(); ++k) image.pixels[k] = 0.101f + 0.37f * float(k);
  writeImage(image, dir.path("rgb.exr"));
  const RgbImage read = readRgbImage(dir.path("rgb.exr"));
  for (std::size_t k = 0; k < image.pixels.size(); ++k) {
    EXPECT_NEAR(read.pixels[k], image.pixels[k], image.pixels[k] * std::ldexp(1.0, -11)) << k;
    EXPECT_NE(read.pixels[k], image.pixels[k]) << "stored as float, not half: " << k;
  }
}

// A data window away from the origin (as compositing tools write crops) is read whole.
TEST(ImageFile, ExrDataWindowAwayFromTheOriginIsRead) {
  const TempDir dir;
  const Imath::Box2i window({10, 20}, {13, 21});
  Imf::Header header(Imath::Box2i({0, 0}, {31, 31}), window);
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  std::vector<float> values(8);
  for (int i = 0; i < 8; ++i) values[i] = float(i);
  Imf::FrameBuffer frame;
  frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, values.data(), window, sizeof(float), 4 * sizeof(float)));
  {
    Imf::OutputFile file(dir.path("crop.exr").c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  const ImageChannels read = readImageChannels(dir.path("crop.exr"));
  EXPECT_EQ(read.width, 4);
  EXPECT_EQ(read.height, 2);
  EXPECT_EQ(read.values, values);
}

// PNG through the OpenImageIO module: 8-bit sRGB as stored.
TEST(ImageFile, PngRoundTripThroughTheOpenImageIOModule) {
  const TempDir dir;
  RgbImage image(3, 2);
  for (std::size_t k = 0; k < image.pixels.size(); ++k) image.pixels[k] = 0.05f * float(k);
  writeImage(image, dir.path("a.png"));
  const ImageChannels read = readImageChannels(dir.path("a.png"));
  ASSERT_EQ(read.names.size(), 3u);
  for (std::size_t k = 0; k < image.pixels.size(); ++k)
    EXPECT_FLOAT_EQ(read.values[k], std::round(255 * linearToSrgb(image.pixels[k])) / 255) << k;
}

// Damaged and foreign files: one error naming the file, whichever library reads it.
TEST(ImageFile, DamagedFilesAreRefusedNamingTheFile) {
  const TempDir dir;
  writeExr(scrambledChannels(), dir.path("whole.exr"));
  const auto size = std::filesystem::file_size(dir.path("whole.exr"));
  std::filesystem::copy_file(dir.path("whole.exr"), dir.path("cut.exr"));
  std::filesystem::resize_file(dir.path("cut.exr"), size - 40);
  std::ofstream(dir.path("noise.png")) << "not an image at all";
  for (const std::string name : {"cut.exr", "noise.png"}) {
    const std::string error = errorOf(dir.path(name));
    EXPECT_NE(error.find(dir.path(name)), std::string::npos) << error;
    EXPECT_NE(error.find("cannot read the image"), std::string::npos) << error;
  }
  EXPECT_NE(errorOf(dir.path("missing.exr")).find("no such image file"), std::string::npos);
}

}  // namespace
}  // namespace vdbappear
