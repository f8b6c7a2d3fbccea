#include "libvdbappear/image/image_file.h"

#include "libvdbappear/image/exr_header_check.h"
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/resource_limits.h"
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

std::string imageFormat(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  if (extension.empty()) throw MediumError(fmt::format("{}: no extension to choose the image format by", path));
  extension = extension.substr(1);
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

void writeImage(const RgbImage& image, const std::string& path) {
  namespace OIIO = OIIO_NAMESPACE;
  const std::string extension = imageFormat(path);
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

int ImageChannels::find(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

void writeExr(const ImageChannels& image, const std::string& path) {
  namespace OIIO = OIIO_NAMESPACE;
  const int n = int(image.names.size());
  if (n == 0 || image.values.size() != std::size_t(image.width) * image.height * n)
    throw MediumError(fmt::format("{}: image channels and values do not match", path));
  AtomicFile file(path);
  auto output = OIIO::ImageOutput::create("exr");
  if (!output) throw MediumError(fmt::format("{}: cannot write .exr images: {}", path, OIIO::geterror()));
  OIIO::ImageSpec spec(image.width, image.height, n, OIIO::TypeDesc::FLOAT);
  spec.channelnames = image.names;
  spec.alpha_channel = -1;
  spec.attribute("compression", "zip");
  bool ok = output->open(file.temporaryPath(), spec) && output->write_image(OIIO::TypeDesc::FLOAT, image.values.data());
  ok = output->close() && ok;
  if (!ok) throw MediumError(fmt::format("{}: cannot write the image: {}", path, output->geterror()));
  file.commit();
}

namespace {

// A header can state any size, and a damaged 425-byte file stated 400 MB of pixels (3.9 s to
// allocate and fail to decode; found by the environment-map fuzz harness). The floats asked for
// must fit the memory a render may hold, and a file of some size can expand to at most this many
// times its bytes: deflate packs at most 1032:1, 8-bit samples become 4-byte floats, and a margin
// of four on top. Small images pass whatever their file.
constexpr double kMaxExpansion = 16384, kAlwaysAllowedBytes = 64 << 20;

void checkStatedImageSize(int width, int height, int channels, const std::string& path) {
  const double bytes = double(width) * height * channels * sizeof(float);
  const double file_bytes = double(std::filesystem::file_size(path));
  if (width <= 0 || height <= 0 || channels <= 0)
    throw MediumError(fmt::format("{}: the image states {}x{} pixels of {} channels", path, width, height, channels));
  if (bytes > double(maxRenderBytes()))
    throw MediumError(fmt::format("{}: a {}x{} image of {} channels ({:.0f} bytes as floats) is beyond the memory "
                                  "limit of {} bytes (VDBAPPEAR_MAX_RENDER_BYTES)",
                                  path, width, height, channels, bytes, maxRenderBytes()));
  if (bytes > std::max(kAlwaysAllowedBytes, kMaxExpansion * file_bytes))
    throw MediumError(fmt::format("{}: a {}x{} image of {} channels ({:.0f} bytes as floats) from a file of {:.0f} "
                                  "bytes: more than {:.0f} times its size, which no image codec packs (damaged?)",
                                  path, width, height, channels, bytes, file_bytes, kMaxExpansion));
}

}  // namespace

ImageChannels readImageChannels(const std::string& path) {
  namespace OIIO = OIIO_NAMESPACE;
  if (!std::filesystem::is_regular_file(path)) throw MediumError(fmt::format("{}: no such image file", path));
  checkExrHeaders(path);
  auto input = OIIO::ImageInput::open(path);
  if (!input) throw MediumError(fmt::format("{}: cannot read the image: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  checkStatedImageSize(spec.width, spec.height, spec.nchannels, path);
  ImageChannels image;
  image.width = spec.width;
  image.height = spec.height;
  image.names = spec.channelnames;
  image.values.resize(std::size_t(spec.width) * spec.height * spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values.data()))
    throw MediumError(fmt::format("{}: cannot read the image: {}", path, input->geterror()));
  return image;
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
