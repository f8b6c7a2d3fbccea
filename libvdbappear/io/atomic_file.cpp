#include "libvdbappear/io/atomic_file.h"

#include "libvdbappear/io/interrupt_cleanup.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <random>
#include <unistd.h>

namespace vdbappear {

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
  const std::filesystem::path path(target_);
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = fmt::format(".{}.tmp.{:08x}", path.filename().string(), entropy());
    const std::string candidate = (path.parent_path() / name).string();
    // Mode 0666: the kernel applies the umask, as for any new file.
    const int fd = open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      close(fd);
      temporary_ = candidate;
      cleanup_slot_ = registerInterruptCleanup(temporary_.c_str());
      return;
    }
    if (errno != EEXIST) break;
  }
  throw MediumError(fmt::format("{}: cannot create the output file: {}", target_, std::strerror(errno)));
}

AtomicFile::~AtomicFile() {
  unregisterInterruptCleanup(cleanup_slot_);
  if (!committed_) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0)
    throw MediumError(fmt::format("{}: cannot write the output file: {}", target_, std::strerror(errno)));
  committed_ = true;
  unregisterInterruptCleanup(cleanup_slot_);
  cleanup_slot_ = -1;
}

}  // namespace vdbappear
