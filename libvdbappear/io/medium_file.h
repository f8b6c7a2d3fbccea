#pragma once
// Reading and writing media (docs/medium.md) as VDB files or streams. Light header: tools include
// it without pulling in OpenVDB; the Medium itself is defined in io/medium.h.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vdbappear {

struct Medium;
using MediumPtr = std::shared_ptr<Medium>;

// Reads and validates a medium (io/medium_validate.h). path "-" reads a VDB stream from stdin.
// Throws MediumError naming the file and the grid.
MediumPtr readMedium(const std::string& path);

// Writes a medium, appending history_line to its `history` metadata and stamping `schema`.
// A file is written to a temporary name in the same folder and renamed when complete, so OUT is
// either the old file or the whole new one. path "-" writes a VDB stream to stdout.
void writeMedium(const Medium& medium, const std::string& path, const std::string& history_line);

// Fails early (MediumError) when `path` could not be written: stdout ("-") is a terminal, the folder
// does not exist or is not writable, or the path is a folder. Tools call it before any work.
void checkWritable(const std::string& path);

// "vdb_tool 0.1.0: vdb_tool --flag value IN OUT", arguments shell-quoted where needed.
std::string historyLine(const std::string& tool, int argc, const char* const* argv);

// How a medium is made up, for reports.
struct GridSummary {
  std::string name;
  std::string type;
  std::uint64_t active_voxels = 0;
  std::uint64_t memory_bytes = 0;
};
struct MediumSummary {
  std::vector<GridSummary> grids;
  std::uint64_t active_voxels = 0;  // of the density grid
  std::uint64_t memory_bytes = 0;   // all grids, in memory
  double voxel_size = 0;            // world units, along x
};
MediumSummary summarize(const Medium& medium);

}  // namespace vdbappear
