#include "libvdbappear/io/resource_limits.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <unistd.h>

namespace vdbappear {

namespace {

// A positive integer from the environment variable `name`, else `fallback` when it is unset.
std::uint64_t limitFromEnvironment(const char* name, std::uint64_t fallback) {
  const char* text = std::getenv(name);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (errno != 0 || *end != '\0' || value == 0 || text[0] == '-')
    throw MediumError(fmt::format("{}='{}': expected a positive integer", name, text));
  return value;
}

std::uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  return pages > 0 && page_size > 0 ? std::uint64_t(pages) * std::uint64_t(page_size) : ~std::uint64_t(0);
}

}  // namespace

std::uint64_t maxTileVoxels() { return limitFromEnvironment("VDBAPPEAR_MAX_TILE_VOXELS", std::uint64_t(1) << 31); }

std::uint64_t maxRenderBytes() { return limitFromEnvironment("VDBAPPEAR_MAX_RENDER_BYTES", physicalMemoryBytes()); }

}  // namespace vdbappear
