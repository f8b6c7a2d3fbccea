#pragma once
// A medium assembled from disjoint parts (the slabs of a streamed reduction, docs/scaling.md §5)
// that holds only its topology in memory: each part is written to a scratch file and read back with
// OpenVDB's delayed loading, so its leaves join the whole's trees with their values left on disk.
// Written out (writeMedium), the whole reads one leaf at a time and frees it once written.
// A scratch file is removed as soon as it is mapped (the mapping keeps it readable while the medium
// lives), so none is left behind however the process ends.
// Internal header: includes OpenVDB.

#include "libvdbappear/io/medium.h"

#include <memory>
#include <string>
#include <vector>

namespace vdbappear {

class SpilledMedium {
 public:
  // Scratch files go in the folder of `output` ("-": the system's temporary folder).
  explicit SpilledMedium(const std::string& output);

  // Validates `part` as a part of a medium (each grid by validateGridPart, then across grids; errors
  // name `source`), then moves its grids that are indexed by voxel to a scratch file and their leaves
  // into the whole. The others (the phase table, exemplar grids: the same in every part) are the
  // first part's. Parts must not share a leaf.
  void add(const Medium& part, const std::string& source);

  // The whole (null before the first part), its values on disk; validated part by part. It keeps
  // what its values need when this object is gone.
  MediumPtr medium() const { return whole_; }

  struct Scratch;  // the scratch files and what their unread leaves refer to

 private:
  std::string folder_;
  MediumPtr whole_;
  std::shared_ptr<Scratch> scratch_;
};

// Whether every grid of `medium` indexed by voxel is one a SpilledMedium made (none was added or
// replaced since): its parts were validated, and writeMedium does not read it whole to validate it.
bool isValidatedInParts(const Medium& medium);

// Writes such a medium as writeVdb would (the same file), reading one leaf at a time: OpenVDB's own
// writer reads all of a grid's leaves into memory first. writeMedium calls it.
void writeValidatedInParts(const std::string& path, const Medium& medium, const openvdb::MetaMap& metadata);

}  // namespace vdbappear
