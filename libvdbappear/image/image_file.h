#pragma once
// Writes images through OpenImageIO, atomically (temporary file, then rename). The format follows
// the extension: .exr keeps linear floats (half precision); .png and others get 8-bit sRGB.

#include "libvdbappear/image/rgb_image.h"

#include <string>

namespace vdbappear {

void writeImage(const RgbImage& image, const std::string& path);

// Linear to sRGB-encoded (IEC 61966-2-1), clamped to [0,1].
float linearToSrgb(float linear);

}  // namespace vdbappear
