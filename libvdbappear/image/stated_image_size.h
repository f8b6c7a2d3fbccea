#pragma once
// The size an image file states, checked before a reader allocates for it.

#include <string>

namespace vdbappear {

// A header can state any size, and a damaged 425-byte file stated 400 MB of pixels (3.9 s to
// allocate and fail to decode; found by the environment-map fuzz harness). The floats asked for
// must fit the memory a render may hold (VDBAPPEAR_MAX_RENDER_BYTES), and a file can expand to at
// most kMaxExpansion times its bytes. Throws MediumError naming the file.
void checkStatedImageSize(int width, int height, int channels, const std::string& path);

}  // namespace vdbappear
