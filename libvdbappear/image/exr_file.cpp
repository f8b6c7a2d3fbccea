#include "libvdbappear/image/exr_file.h"

#include "libvdbappear/image/stated_image_size.h"
#include "libvdbappear/util/error.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <fstream>
#include <tuple>
#include <type_traits>
#include <vector>

namespace vdbappear {

namespace {

constexpr std::uint32_t kExrMagic = 20000630;  // the file's first four bytes, little-endian

// A channel's layer (before the last dot) and its rank in its layer: R, G, B, A first.
std::tuple<std::string, int, std::string> channelOrderKey(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  const std::string layer = dot == std::string::npos ? "" : name.substr(0, dot);
  const std::string suffix = dot == std::string::npos ? name : name.substr(dot + 1);
  static constexpr std::array<const char*, 4> kFirst = {"R", "G", "B", "A"};
  const auto it = std::find(kFirst.begin(), kFirst.end(), suffix);
  return {layer, int(it - kFirst.begin()), name};
}

// Channel `c` of pixels interleaved n to a pixel, row 0 at the data window's top.
template <typename T>
Imf::Slice sliceOf(const T* pixels, std::size_t c, std::size_t n, const Imath::Box2i& window) {
  const int width = window.max.x - window.min.x + 1;
  const Imf::PixelType type = std::is_same_v<T, half> ? Imf::HALF : Imf::FLOAT;
  return Imf::Slice::Make(type, pixels + c, window, sizeof(T) * n, sizeof(T) * n * width);
}

}  // namespace

bool isExrFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char bytes[4] = {};
  if (!in.read(reinterpret_cast<char*>(bytes), 4)) return false;
  const std::uint32_t magic = bytes[0] | bytes[1] << 8 | bytes[2] << 16 | std::uint32_t(bytes[3]) << 24;
  return magic == kExrMagic;
}

void writeExrChannels(const ImageChannels& image, ExrPixelType pixel_type, const std::string& file_path,
                      const std::string& name_for_errors) {
  const std::size_t n = image.names.size();
  if (n == 0 || image.width <= 0 || image.height <= 0 ||
      image.values.size() != std::size_t(image.width) * image.height * n)
    throw MediumError(fmt::format("{}: image channels and values do not match", name_for_errors));
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    // OpenEXR's writer does not convert: half channels are written from half values.
    const bool is_half = pixel_type == ExrPixelType::half;
    const std::vector<half> halves = is_half ? std::vector<half>(image.values.begin(), image.values.end())
                                             : std::vector<half>();
    for (std::size_t c = 0; c < n; ++c) {
      header.channels().insert(image.names[c], Imf::Channel(is_half ? Imf::HALF : Imf::FLOAT));
      frame.insert(image.names[c], is_half ? sliceOf(halves.data(), c, n, header.dataWindow())
                                           : sliceOf(image.values.data(), c, n, header.dataWindow()));
    }
    Imf::OutputFile file(file_path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot write the image: {}", name_for_errors, e.what()));
  }
}

ImageChannels readExrChannels(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    ImageChannels image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
      image.names.push_back(it.name());
    std::sort(image.names.begin(), image.names.end(),
              [](const std::string& a, const std::string& b) { return channelOrderKey(a) < channelOrderKey(b); });
    const std::size_t n = image.names.size();
    checkStatedImageSize(image.width, image.height, int(n), path);
    image.values.resize(std::size_t(image.width) * image.height * n);
    Imf::FrameBuffer frame;
    for (std::size_t c = 0; c < n; ++c) frame.insert(image.names[c], sliceOf(image.values.data(), c, n, window));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const MediumError&) {
    throw;
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot read the image: {}", path, e.what()));
  }
}

}  // namespace vdbappear
