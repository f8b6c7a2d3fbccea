#pragma once
// Image files, written atomically (temporary file, then rename). The format follows the extension:
// .exr keeps linear floats (half precision), through OpenEXR; .png and others get 8-bit sRGB,
// through OpenImageIO, loaded only when such a file is read or written (image/oiio_codec.h).

#include "libvdbappear/image/rgb_image.h"

#include <string>
#include <vector>

namespace vdbappear {

void writeImage(const RgbImage& image, const std::string& path);

// The format an image path is written in: its extension, lower-cased, without the dot ("exr",
// "png"). Throws MediumError when the path has no extension.
std::string imageFormat(const std::string& path);

// Named float channels, interleaved per pixel (e.g. R, G, B, variance.R, ..., cluster.0, ...).
struct ImageChannels {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<float> values;  // width * height * names.size(), row 0 at the top
  int find(const std::string& name) const;  // index of a channel, -1 if absent
};

// A 32-bit float OpenEXR file with these channels (zip compression), atomically.
void writeExr(const ImageChannels& image, const std::string& path);
// Every channel of an image file (EXR, PNG, ...) as floats (PNG: 0..1, sRGB-encoded as stored).
// OpenEXR files (by their magic number) in OpenImageIO's channel order: R, G, B, A first.
ImageChannels readImageChannels(const std::string& path);
// The first three channels as RGB (one channel: grey); throws MediumError naming the file.
RgbImage readRgbImage(const std::string& path);
RgbImage rgbOf(const ImageChannels& channels);

// Linear to sRGB-encoded (IEC 61966-2-1), clamped to [0,1].
float linearToSrgb(float linear);

}  // namespace vdbappear
