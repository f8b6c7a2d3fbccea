// libvdbappear_oiio.so: the OpenImageIO side of image/oiio_codec.h.
#include "libvdbappear/image/oiio_codec.h"
#include "libvdbappear/image/stated_image_size.h"
#include "libvdbappear/util/error.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

namespace vdbappear {

namespace {

namespace OIIO = OIIO_NAMESPACE;

void writeRgb8(const std::uint8_t* rgb, int width, int height, const std::string& format, const std::string& file_path,
               const std::string& name_for_errors) {
  auto output = OIIO::ImageOutput::create(format);  // by format: a temporary name has no extension
  if (!output)
    throw MediumError(fmt::format("{}: cannot write .{} images: {}", name_for_errors, format, OIIO::geterror()));
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  bool ok = output->open(file_path, spec) && output->write_image(OIIO::TypeDesc::UINT8, rgb);
  ok = output->close() && ok;
  if (!ok) throw MediumError(fmt::format("{}: cannot write the image: {}", name_for_errors, output->geterror()));
}

ImageChannels read(const std::string& path) {
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

constexpr OiioCodec kCodec{writeRgb8, read};

}  // namespace

}  // namespace vdbappear

extern "C" const vdbappear::OiioCodec* vdbappear_oiio_codec() { return &vdbappear::kCodec; }
