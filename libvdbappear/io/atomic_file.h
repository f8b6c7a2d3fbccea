#pragma once
// Writing a file so that readers see either the old file or the whole new one, never a part.

#include <string>

namespace vdbappear {

// Reserves a temporary file next to `target`; commit() renames it over `target`. If commit() is
// never called (an exception on the way), the destructor removes the temporary file, and if the
// process is interrupted by SIGINT, SIGTERM or SIGHUP meanwhile, the signal handler does
// (io/interrupt_cleanup.h).
class AtomicFile {
 public:
  explicit AtomicFile(std::string target);  // throws MediumError if the folder is not writable
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& temporaryPath() const { return temporary_; }
  void commit();

 private:
  std::string target_;
  std::string temporary_;
  bool committed_ = false;
  int cleanup_slot_ = -1;
};

}  // namespace vdbappear
