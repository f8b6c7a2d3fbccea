#include "libvdbappear/io/mapped_pages.h"

#include <sys/mman.h>

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace vdbappear {

namespace {

// A line of /proc/self/maps names the file after its first '/', with " (deleted)" once it is removed.
bool mapsFile(const std::string& line, std::size_t at, const std::string& file) {
  static const std::string kDeleted = " (deleted)";
  const std::size_t length = line.size() - at;
  return line.compare(at, std::string::npos, file) == 0 ||
         (length == file.size() + kDeleted.size() && line.compare(at, file.size(), file) == 0 &&
          line.compare(at + file.size(), std::string::npos, kDeleted) == 0);
}

}  // namespace

void releaseMappedPages(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& path : paths) {
    std::error_code error;
    const std::filesystem::path absolute = std::filesystem::absolute(path, error);
    if (error) continue;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(absolute, error);
    files.push_back((error ? absolute : canonical).string());
  }
  if (files.empty()) return;
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const std::size_t at = line.find('/');
    if (at == std::string::npos) continue;
    for (const std::string& file : files) {
      if (!mapsFile(line, at, file)) continue;
      std::uintptr_t begin = 0, end = 0;
      if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR, &begin, &end) == 2 && end > begin)
        madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
    }
  }
}

}  // namespace vdbappear
