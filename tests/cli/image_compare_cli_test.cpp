// vdb_image_compare from the command line: masks.
#include "libvdbappear/image/image_file.h"

#include "cli/run_command.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace vdbappear {
namespace {

using test::quote;
using test::runCommand;
using test::TempDir;

const std::string kCompare = quote(VDB_IMAGE_COMPARE);

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

}  // namespace
}  // namespace vdbappear
