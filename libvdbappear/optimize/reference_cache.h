#pragma once
// Reference images of the full-resolution medium, rendered once and kept on disk under a content
// address: the hash of the medium file's bytes and of every render setting, so that any run of any
// tool that asks for the same image under the same settings finds it. Hashes are XXH3-128 (xxHash).
//
// A cache file is a text header line
//   vdbappear-reference FORMAT VERSION WIDTH HEIGHT CHECKSUM
// then WIDTH * HEIGHT * 4 little-endian floats (R, G, B and the alpha AOV per pixel, row 0 at the
// top); CHECKSUM is the XXH3-64 of those bytes in hex. Files are written through a temporary name and renamed. Light header.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

// XXH3-128 of a file's bytes, as 32 hex digits; throws MediumError naming the file.
std::string hashFile(const std::string& path);
// XXH3-128 of a string, as 32 hex digits.
std::string hashText(const std::string& text);

struct CachedImage {
  int width = 0, height = 0;
  std::vector<float> rgba;  // width * height * 4: RGB and alpha (RenderResult::alpha)
};

class ReferenceCache {
 public:
  static constexpr int kFormat = 2;

  // folder "": no cache (find finds nothing, store stores nothing). The folder is created on the
  // first store.
  explicit ReferenceCache(std::string folder);

  bool enabled() const { return !folder_.empty(); }
  const std::string& folder() const { return folder_; }
  std::string pathOf(const std::string& key) const;  // FOLDER/KEY.ref

  // The image stored under key, if there is one. Throws MediumError naming the file when it is
  // truncated, corrupt, or written by another format or version of vdbappear (delete it, or use
  // another folder: a silent re-render would hide that the renderer changed).
  std::optional<CachedImage> find(const std::string& key) const;
  void store(const std::string& key, const CachedImage& image) const;

 private:
  std::string folder_;
};

// The default folder: $VDBAPPEAR_CACHE, else $XDG_CACHE_HOME/vdbappear, else ~/.cache/vdbappear.
std::string defaultCacheFolder();

}  // namespace vdbappear
