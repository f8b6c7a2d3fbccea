// vdb_image_compare: a render against a reference: mean intensities, RMSE, a false-colour error map.
#include "tool_main.h"

#include "libvdbappear/image/image_compare.h"
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <filesystem>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_image_compare";

constexpr const char* kExamples = R"(Examples:
  vdb_image_compare full.exr naive4x.exr --error-map error.png --report -
  vdb_image_compare ref.exr test.exr --side-by-side compare.png --range 0.25
  vdb_image_compare full.exr lobes4x.exr --foreground --tile 8 --report -
  vdb_image_compare full.exr model4x.exr --foreground --mask block_borders.pfm --report -
  vdb_image_compare uncached.exr cached.exr --layer sss.S --mask uncached.exr:sss.hit   (vdb_render --aov sss)
The error map is the signed relative error per pixel: red where TEST is brighter than REFERENCE,
blue where darker, saturated at --range (default 0.5 = 50%). --tile N compares the means of N x N
pixel tiles (the numbers and the maps): the look at that scale, with less noise.)";

// The channels LAYER.R, LAYER.G, LAYER.B of an image (vdb_render's AOVs), or R, G, B for "".
RgbImage layerOf(const ImageChannels& image, const std::string& layer, const std::string& path) {
  if (layer.empty()) return rgbOf(image);
  RgbImage rgb(image.width, image.height);
  const std::size_t n = image.names.size();
  for (int c = 0; c < 3; ++c) {
    const int k = image.find(layer + "." + "RGB"[c]);
    if (k < 0) throw std::runtime_error(fmt::format("{}: no channel {}.{} (--layer)", path, layer, "RGB"[c]));
    for (std::size_t i = 0; i < std::size_t(image.width) * std::size_t(image.height); ++i)
      rgb.pixels[3 * i + std::size_t(c)] = image.values[i * n + std::size_t(k)];
  }
  return rgb;
}

// mask &= (the channel of the image at `spec` = PATH[:CHANNEL], its first by default, > 0.5); an
// empty mask means every pixel.
void restrictToMask(const std::string& spec, int width, int height, std::vector<bool>& mask) {
  const std::size_t colon = spec.rfind(':');
  const bool named = colon != std::string::npos && !std::filesystem::exists(spec);
  const std::string path = named ? spec.substr(0, colon) : spec;
  const ImageChannels image = readImageChannels(path);
  int channel = 0;
  if (named) {
    channel = image.find(spec.substr(colon + 1));
    if (channel < 0) throw std::runtime_error(fmt::format("{}: no channel '{}' for --mask", path, spec.substr(colon + 1)));
  }
  if (image.width != width || image.height != height)
    throw std::runtime_error(fmt::format("{}: the mask is {}x{}, the images {}x{}", path, image.width, image.height,
                                         width, height));
  const std::size_t pixels = std::size_t(width) * height;
  if (mask.empty()) mask.assign(pixels, true);
  for (std::size_t i = 0; i < pixels; ++i) mask[i] = mask[i] && image.values[i * image.names.size() + std::size_t(channel)] > 0.5f;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Compares an image with a reference (EXR or any format OpenImageIO reads).", kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  std::string reference, test, error_map, side_by_side, report, mask_image, layer, test_layer;
  double range = 0.5;
  bool foreground = false;
  int tile = 1;
  app.add_option("REFERENCE", reference, "reference image")->required();
  app.add_option("TEST", test, "image to compare")->required();
  app.add_option("--error-map", error_map, "write the false-colour relative error map (PNG or EXR)");
  app.add_option("--side-by-side", side_by_side, "write REFERENCE | TEST | error map as one image");
  app.add_option("--range", range, "relative error at which the map saturates (default 0.5)")->check(CLI::PositiveNumber);
  app.add_flag("--foreground", foreground, "count only pixels where REFERENCE's alpha channel A > 0.5 (vdb_render --aov alpha)");
  app.add_option("--mask", mask_image, "FILE[:CHANNEL]: count only pixels where this image's first channel (or the "
                                      "one named) is above 0.5 (with --foreground: pixels in both)");
  app.add_option("--layer", layer, "compare the channels LAYER.R, LAYER.G, LAYER.B of both images (EXR AOVs, e.g. "
                                   "vdb_render --aov sss: sss.S) instead of R, G, B");
  app.add_option("--test-layer", test_layer, "TEST's layer, when it differs from --layer's (e.g. sss.S1)");
  app.add_option("--tile", tile, "compare the means of N x N pixel tiles (a foreground tile: most of its pixels are)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--report", report, "write the numbers as JSON (- for stdout; default: a line on stdout)");

  return tool::run(app, argc, argv, [&] {
    const ImageChannels channels = readImageChannels(reference);  // once: RGB, and alpha for --foreground
    const RgbImage full_a = layerOf(channels, layer, reference);
    if (test_layer.empty()) test_layer = layer;
    const RgbImage full_b = test_layer.empty() ? readRgbImage(test) : layerOf(readImageChannels(test), test_layer, test);
    checkSameSize(full_a, full_b);
    const RgbImage a = tileMeans(full_a, tile), b = tileMeans(full_b, tile);
    std::vector<bool> mask;
    if (foreground) {
      const int alpha = channels.find("A");
      if (alpha < 0) throw std::runtime_error(reference + ": --foreground needs an alpha channel A (vdb_render --aov alpha)");
      for (std::size_t i = 0; i < std::size_t(channels.width) * channels.height; ++i)
        mask.push_back(channels.values[i * channels.names.size() + alpha] > 0.5f);
    }
    if (!mask_image.empty()) restrictToMask(mask_image, channels.width, channels.height, mask);
    mask = tileMask(mask, channels.width, channels.height, tile);
    const ImageComparison c = compareImages(a, b, mask);
    const RgbImage map = relativeErrorMap(a, b, range);
    if (!error_map.empty()) writeImage(map, error_map);
    if (!side_by_side.empty()) writeImage(sideBySide({&a, &b, &map}), side_by_side);
    const nlohmann::json json = {{"reference", reference}, {"test", test}, {"layer", layer}, {"test_layer", test_layer}, {"foreground_only", foreground},
                                 {"mask", mask_image}, {"tile", tile},
                                 {"mean_reference", c.mean_reference}, {"mean_test", c.mean_test},
                                 {"mean_relative_error", c.mean_relative_error}, {"rmse", c.rmse},
                                 {"relative_rmse", c.relative_rmse}, {"max_abs_error", c.max_abs_error},
                                 {"worst_relative_error", c.worst_relative_error}};
    if (!report.empty()) {
      tool::writeJsonReport(report, json);
    } else {
      fmt::print("mean {:.6g} vs {:.6g} ({:+.2f}%), RMSE {:.4g} ({:.2f}% of the mean), worst {} {:.2f}%\n",
                 c.mean_reference, c.mean_test, 100 * c.mean_relative_error, c.rmse, 100 * c.relative_rmse,
                 tile > 1 ? fmt::format("{}x{} tile", tile, tile) : std::string("pixel"), 100 * c.worst_relative_error);
    }
    return 0;
  });
}
