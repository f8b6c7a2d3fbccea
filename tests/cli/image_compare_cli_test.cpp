// vdb_image_compare from the command line: masks.
#include "libvdbappear/image/image_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>

namespace vdbappear {
namespace {

using test::kCompare;
using test::quote;
using test::runCommand;
using test::TempDir;

// A 4x2 RGB image whose left half is `left` and right half `right`.
std::string halves(const TempDir& dir, const std::string& name, float left, float right) {
  ImageChannels image;
  image.width = 4;
  image.height = 2;
  image.names = {"R", "G", "B"};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) image.values.push_back(x < 2 ? left : right);
  const std::string path = dir.path(name);
  writeExr(image, path);
  return path;
}

TEST(ImageCompareCli, MaskCountsOnlyItsPixels) {
  TempDir dir;
  const std::string reference = halves(dir, "ref.exr", 1, 1), test = halves(dir, "test.exr", 1.5f, 1);
  const std::string left = halves(dir, "left.exr", 1, 0), right = halves(dir, "right.exr", 0, 1);
  const auto whole = nlohmann::json::parse(runCommand(kCompare + " " + quote(reference) + " " + quote(test) + " --report -").out);
  EXPECT_NEAR(whole["mean_relative_error"].get<double>(), 0.25, 1e-6);
  const auto l = runCommand(kCompare + " " + quote(reference) + " " + quote(test) + " --mask " + quote(left) + " --report -");
  ASSERT_EQ(l.status, 0) << l.err;
  EXPECT_NEAR(nlohmann::json::parse(l.out)["mean_relative_error"].get<double>(), 0.5, 1e-6);
  const auto r = runCommand(kCompare + " " + quote(reference) + " " + quote(test) + " --mask " + quote(right) + " --report -");
  EXPECT_NEAR(nlohmann::json::parse(r.out)["mean_relative_error"].get<double>(), 0.0, 1e-6);
  // A mask of another size is refused, naming it.
  ImageChannels small;
  small.width = small.height = 1;
  small.names = {"R"};
  small.values = {1};
  writeExr(small, dir.path("small.exr"));
  const auto bad = runCommand(kCompare + " " + quote(reference) + " " + quote(test) + " --mask " + quote(dir.path("small.exr")));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("small.exr: the mask is 1x1"), std::string::npos) << bad.err;
}

// The header of an OpenEXR file of 5 KB (PIZ-compressed scanlines, an offset table of zeros)
// stating 20000x20000 pixels: 1.6 GB of floats. A damaged environment map of 425 bytes stated
// 400 MB and took 3.9 s to allocate and fail to decode (fuzz finding, docs/reliability.md §2).
std::string exrStating(int width, int height) {
  const auto le32 = [](std::int32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const auto attribute = [&](const std::string& name, const std::string& type, const std::string& value) {
    return name + '\0' + type + '\0' + le32(std::int32_t(value.size())) + value;
  };
  const std::string box = le32(0) + le32(0) + le32(width - 1) + le32(height - 1);
  const std::string one = le32(0x3f800000);  // 1.0f
  const std::string channel = std::string("R") + '\0' + le32(1) + std::string(4, '\0') + le32(1) + le32(1) + '\0';
  std::string bytes = le32(20000630) + le32(2) + attribute("channels", "chlist", channel) +
                      attribute("compression", "compression", std::string(1, '\x04')) +
                      attribute("dataWindow", "box2i", box) + attribute("displayWindow", "box2i", box) +
                      attribute("lineOrder", "lineOrder", std::string(1, '\0')) + attribute("pixelAspectRatio", "float", one) +
                      attribute("screenWindowCenter", "v2f", std::string(8, '\0')) + attribute("screenWindowWidth", "float", one) + '\0';
  return bytes + std::string(8 * ((height + 31) / 32) + 64, '\0');
}

TEST(ImageCompareCli, AnImageStatingFarMorePixelsThanItsFileCanHoldIsRefusedBeforeAllocation) {
  TempDir dir;
  const std::string image = dir.path("huge.exr");
  std::ofstream(image, std::ios::binary) << exrStating(20000, 20000);
  const auto r = runCommand(kCompare + " " + quote(image) + " " + quote(image) + " --report -");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find(image + ": a 20000x20000 image of 1 channels (1600000000 bytes as floats) from a file of"),
            std::string::npos) << r.err;
}

}  // namespace
}  // namespace vdbappear
