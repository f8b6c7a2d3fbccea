#pragma once
// OpenEXR files through OpenEXR itself. OpenImageIO pulls in some 260 shared libraries, 0.4 s and
// 128 MB at every process start (docs/rendering.md §7); OpenEXR a dozen. Internal to
// libvdbappear_image: tools call image/image_file.h.

#include "libvdbappear/image/image_file.h"

#include <string>

namespace vdbappear {

// Whether the file starts with OpenEXR's magic number.
bool isExrFile(const std::string& path);

enum class ExrPixelType { half, float32 };

// Writes the channels, zip-compressed, to `file_path` (no rename: the caller's AtomicFile does it);
// errors name `name_for_errors`.
void writeExrChannels(const ImageChannels& image, ExrPixelType pixel_type, const std::string& file_path,
                      const std::string& name_for_errors);

// Every channel as floats, in OpenImageIO's order (R, G, B, A first within each layer, the
// unlayered channels first), so that rgbOf finds the colour in the first three.
ImageChannels readExrChannels(const std::string& path);

}  // namespace vdbappear
