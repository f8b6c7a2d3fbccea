#include "libvdbappear/optimize/reference_cache.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>
#include <xxhash.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vdbappear {

namespace {

std::string hex128(XXH128_hash_t h) { return fmt::format("{:016x}{:016x}", h.high64, h.low64); }

std::uint64_t checksum(const std::vector<float>& v) { return XXH3_64bits(v.data(), v.size() * sizeof(float)); }

}  // namespace

std::string hashFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MediumError(fmt::format("{}: cannot be read for its content hash", path));
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    XXH3_128bits_update(state, buffer.data(), std::size_t(in.gcount()));
  }
  const XXH128_hash_t h = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  if (in.bad()) throw MediumError(fmt::format("{}: read error while hashing", path));
  return hex128(h);
}

std::string hashText(const std::string& text) { return hex128(XXH3_128bits(text.data(), text.size())); }

ReferenceCache::ReferenceCache(std::string folder) : folder_(std::move(folder)) {}

std::string ReferenceCache::pathOf(const std::string& key) const {
  return (std::filesystem::path(folder_) / (key + ".ref")).string();
}

std::optional<CachedImage> ReferenceCache::find(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  const std::string path = pathOf(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string header;
  std::getline(in, header);
  std::istringstream fields(header);
  std::string magic, version, sum;
  int format = 0;
  CachedImage image;
  if (!(fields >> magic >> format >> version >> image.width >> image.height >> sum) || magic != "vdbappear-reference")
    throw MediumError(fmt::format("{}: not a reference image of this cache (bad header); delete it", path));
  if (format != kFormat || version != kVersion)
    throw MediumError(fmt::format("{}: written by vdbappear {} (cache format {}), this is {} (format {}): delete it, "
                                  "or give another --cache folder", path, version, format, kVersion, kFormat));
  if (image.width < 1 || image.height < 1 || image.width > 16384 || image.height > 16384)
    throw MediumError(fmt::format("{}: bad image size {}x{} in the header; delete it", path, image.width, image.height));
  image.rgba.resize(std::size_t(image.width) * image.height * 4);
  in.read(reinterpret_cast<char*>(image.rgba.data()), std::streamsize(image.rgba.size() * sizeof(float)));
  if (std::size_t(in.gcount()) != image.rgba.size() * sizeof(float) || in.peek() != std::char_traits<char>::eof())
    throw MediumError(fmt::format("{}: truncated or too long ({} of {} bytes of pixels); delete it", path, in.gcount(),
                                  image.rgba.size() * sizeof(float)));
  if (fmt::format("{:016x}", checksum(image.rgba)) != sum)
    throw MediumError(fmt::format("{}: corrupt (checksum mismatch); delete it", path));
  return image;
}

void ReferenceCache::store(const std::string& key, const CachedImage& image) const {
  if (!enabled()) return;
  std::error_code error;
  std::filesystem::create_directories(folder_, error);
  if (error) throw MediumError(fmt::format("{}: cannot create the cache folder: {}", folder_, error.message()));
  const std::string path = pathOf(key);
  AtomicFile file(path);
  {
    std::ofstream out(file.temporaryPath(), std::ios::binary | std::ios::trunc);
    out << fmt::format("vdbappear-reference {} {} {} {} {:016x}\n", kFormat, kVersion, image.width, image.height,
                       checksum(image.rgba));
    if (image.rgba.size() != std::size_t(image.width) * image.height * 4)
      throw std::invalid_argument("ReferenceCache::store: the image is not width x height x 4");
    out.write(reinterpret_cast<const char*>(image.rgba.data()), std::streamsize(image.rgba.size() * sizeof(float)));
    out.close();
    if (!out) throw MediumError(fmt::format("{}: cannot write the cache file", path));
  }
  file.commit();
}

std::string defaultCacheFolder() {
  if (const char* own = std::getenv("VDBAPPEAR_CACHE"); own && *own) return own;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (std::filesystem::path(xdg) / "vdbappear").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (std::filesystem::path(home) / ".cache" / "vdbappear").string();
  return "";
}

}  // namespace vdbappear
