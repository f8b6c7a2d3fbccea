#pragma once
// Parts of a medium parked on disk between two passes over a file's slabs (docs/scaling.md §5): a
// reduction whose second pass needs what only the whole first pass can give (vdb_lobe_cluster's
// clusters) keeps each first-pass part here instead of in memory. The parts are appended to one
// scratch file in the output's folder, removed as soon as it is open, so that nothing is left behind
// however the process ends; leaf values are compressed only by their active masks (fast).
// Internal header: includes OpenVDB (through io/medium.h).

#include "libvdbappear/io/medium.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace vdbappear {

// The folder of `output` ("-": the system's temporary folder), where scratch files go.
std::string scratchFolderFor(const std::string& output);

class ScratchParts {
 public:
  // Throws MediumError naming the folder if no file can be made there.
  explicit ScratchParts(const std::string& output);

  // Appends a part (its grids and file-level metadata); returns its index. MediumError on a failed write.
  std::size_t put(const Medium& part);
  // Part i read back whole, validated as a VDB stream is (readMediumStream), `source` naming it in messages.
  MediumPtr take(std::size_t i, const std::string& source);

  std::size_t size() const { return offsets_.size(); }
  std::uint64_t bytes() const { return end_; }  // on disk

 private:
  std::string path_;  // for messages: the file is already removed
  std::fstream file_;
  std::vector<std::streamoff> offsets_;
  std::streamoff end_ = 0;
};

}  // namespace vdbappear
