#include "libvdbappear/image/stated_image_size.h"

#include "libvdbappear/io/resource_limits.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

namespace vdbappear {

namespace {

// Deflate packs at most 1032:1, 8-bit samples become 4-byte floats, and a margin of four on top.
// Small images pass whatever their file.
constexpr double kMaxExpansion = 16384, kAlwaysAllowedBytes = 64 << 20;

}  // namespace

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

}  // namespace vdbappear
