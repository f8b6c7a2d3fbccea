#include "libvdbappear/io/atomic_file.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace vdbappear {

namespace {
mode_t defaultFileMode() {
  const mode_t mask = umask(0);
  umask(mask);
  return 0666 & ~mask;
}
}  // namespace

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
  const std::filesystem::path path(target_);
  if (std::filesystem::is_directory(path)) throw MediumError(fmt::format("{}: is a directory", target_));
  std::string pattern = (path.parent_path() / ("." + path.filename().string() + ".tmp.XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0) throw MediumError(fmt::format("{}: cannot create the output file: {}", target_, std::strerror(errno)));
  fchmod(fd, defaultFileMode());
  close(fd);
  temporary_ = name.data();
}

AtomicFile::~AtomicFile() {
  if (!committed_) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0)
    throw MediumError(fmt::format("{}: cannot write the output file: {}", target_, std::strerror(errno)));
  committed_ = true;
}

}  // namespace vdbappear
