#pragma once
// Image formats other than OpenEXR (PNG, JPEG, TIFF, HDR, ...) through OpenImageIO, in a module
// of its own (libvdbappear_oiio.so) that libvdbappear_image loads the first time such a file is
// read or written: linking OpenImageIO costs every process 0.4 s and 128 MB at start
// (docs/rendering.md §7), whether it writes a PNG or not. Internal to libvdbappear_image.

#include "libvdbappear/image/image_file.h"

#include <cstdint>
#include <string>

namespace vdbappear {

// The module's entry points. Both throw MediumError naming the file.
struct OiioCodec {
  // 8-bit sRGB pixels, RGB interleaved, row 0 at the top, in `format` (an extension: "png") to
  // `file_path`; errors name `name_for_errors`.
  void (*write_rgb8)(const std::uint8_t* rgb, int width, int height, const std::string& format,
                     const std::string& file_path, const std::string& name_for_errors);
  // Every channel as floats (8-bit formats: 0..1, sRGB-encoded as stored).
  ImageChannels (*read)(const std::string& path);
};

// Loads the module from the folder libvdbappear_image lies in (build tree or install), once per
// process as the dynamic loader keeps it; throws MediumError naming `path` when it cannot.
const OiioCodec& oiioCodec(const std::string& path);

}  // namespace vdbappear

// The one symbol the module exports.
extern "C" const vdbappear::OiioCodec* vdbappear_oiio_codec();
