#include "libvdbappear/image/image_file.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/util/error.h"

#include <OpenImageIO/imageio.h>
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

void writeImage(const RgbImage& image, const std::string& path) {
  namespace OIIO = OIIO_NAMESPACE;
  std::string extension = std::filesystem::path(path).extension().string();
  if (extension.empty()) throw MediumError(fmt::format("{}: no extension to choose the image format by", path));
  extension = extension.substr(1);
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  AtomicFile file(path);  // before the writer, so the writer closes the temporary file first
  auto output = OIIO::ImageOutput::create(extension);  // by format: the temporary name has no extension
  if (!output) throw MediumError(fmt::format("{}: cannot write .{} images: {}", path, extension, OIIO::geterror()));
  const bool is_float = extension == "exr";
  OIIO::ImageSpec spec(image.width, image.height, 3, is_float ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  if (!is_float) spec.attribute("oiio:ColorSpace", "sRGB");
  bool ok = output->open(file.temporaryPath(), spec);
  if (ok && is_float) {
    ok = output->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
  } else if (ok) {
    std::vector<std::uint8_t> bytes(image.pixels.size());
    std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(),
                   [](float v) { return std::uint8_t(std::lround(255 * linearToSrgb(v))); });
    ok = output->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  ok = output->close() && ok;
  if (!ok) throw MediumError(fmt::format("{}: cannot write the image: {}", path, output->geterror()));
  file.commit();
}

}  // namespace vdbappear
