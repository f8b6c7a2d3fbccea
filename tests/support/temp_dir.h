#pragma once
// A fresh folder for one test's files, removed with everything in it when the test ends.

#include <filesystem>
#include <string>
#include <vector>

namespace vdbappear::test {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string path(const std::string& name) const { return (root_ / name).string(); }
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
};

// The whole content of a file ("" if it cannot be read).
std::string readFileBytes(const std::string& path);

// Every file name in a folder (temporary files included), sorted.
std::vector<std::string> listFiles(const std::filesystem::path& folder);

}  // namespace vdbappear::test
