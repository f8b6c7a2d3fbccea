#pragma once
// Applying a grid mapping (io/grid_mapping.h) to the grids of a file as it is read. Internal header:
// includes OpenVDB.

#include "libvdbappear/io/grid_mapping.h"

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace vdbappear {

struct MappedGrids {
  openvdb::GridPtrVec grids;
  std::vector<GridRule> applied;   // the explicit rules, then the preset's that were applied
  std::vector<std::string> notes;  // one line each: what the preset mapped, or left and why
};

// The grids with each rule's role made from its sources, the explicit rules' first, then those of
// the preset (io/grid_presets.h): the sources are consumed (removed), a grid already named like the
// role is replaced, and the rest are kept in order. Each made grid passes validateGrid. Throws
// MediumError naming `source` and the rule: a missing source grid, a source of the wrong value
// type, three sources with different transforms, values the role does not allow. A detected
// preset's rule (kAuto) whose grid the role does not allow is left out with a note instead.
MappedGrids applyGridMapping(const openvdb::GridPtrVec& grids, const GridMapping& mapping, const std::string& source);

}  // namespace vdbappear
