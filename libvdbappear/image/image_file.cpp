#include "libvdbappear/image/image_file.h"

#include "libvdbappear/image/exr_file.h"
#include "libvdbappear/image/exr_header_check.h"
#include "libvdbappear/image/oiio_codec.h"
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>

namespace vdbappear {

float linearToSrgb(float linear) {
  const float c = linear >= 0 ? std::min(linear, 1.0f) : 0.0f;  // NaN and negatives: black
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

std::string imageFormat(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  if (extension.empty()) throw MediumError(fmt::format("{}: no extension to choose the image format by", path));
  extension = extension.substr(1);
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

void writeImage(const RgbImage& image, const std::string& path) {
  const std::string extension = imageFormat(path);
  AtomicFile file(path);
  if (extension == "exr") {
    ImageChannels channels{image.width, image.height, {"R", "G", "B"}, image.pixels};
    writeExrChannels(channels, ExrPixelType::half, file.temporaryPath(), path);
  } else {
    std::vector<std::uint8_t> bytes(image.pixels.size());
    std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(),
                   [](float v) { return std::uint8_t(std::lround(255 * linearToSrgb(v))); });
    oiioCodec(path).write_rgb8(bytes.data(), image.width, image.height, extension, file.temporaryPath(), path);
  }
  file.commit();
}

int ImageChannels::find(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

void writeExr(const ImageChannels& image, const std::string& path) {
  AtomicFile file(path);
  writeExrChannels(image, ExrPixelType::float32, file.temporaryPath(), path);
  file.commit();
}

ImageChannels readImageChannels(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw MediumError(fmt::format("{}: no such image file", path));
  if (!isExrFile(path)) return oiioCodec(path).read(path);
  checkExrHeaders(path);
  return readExrChannels(path);
}

RgbImage readRgbImage(const std::string& path) { return rgbOf(readImageChannels(path)); }

RgbImage rgbOf(const ImageChannels& channels) {
  const int n = int(channels.names.size());
  RgbImage image(channels.width, channels.height);
  for (std::size_t i = 0; i < std::size_t(channels.width) * channels.height; ++i)
    for (int c = 0; c < 3; ++c) image.pixels[3 * i + c] = channels.values[i * n + std::min(c, n - 1)];
  return image;
}

}  // namespace vdbappear
