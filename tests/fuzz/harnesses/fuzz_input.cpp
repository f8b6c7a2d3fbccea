#include "fuzz/harnesses/fuzz_input.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

namespace vdbappear::fuzz {

namespace fs = std::filesystem;

namespace {

// Made on first use, removed when the process ends normally (a crash leaves it, with the input).
class InputFolder {
 public:
  InputFolder() {
    const char* tmp = std::getenv("TMPDIR");
    path_ = fs::path(tmp && *tmp ? tmp : "/tmp") / ("vdbappear-fuzz-" + std::to_string(getpid()));
    fs::create_directories(path_);
  }
  ~InputFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
  static const InputFolder folder;
  const fs::path path = folder.path() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path.string();
}

void expectNamed(const std::exception& error, const std::string& path) {
  if (std::string(error.what()).find(path) != std::string::npos) return;
  std::fprintf(stderr, "fuzz harness: an error that does not name the file %s: %s\n", path.c_str(), error.what());
  std::abort();
}

}  // namespace vdbappear::fuzz
