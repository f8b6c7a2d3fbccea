#pragma once
// Applying a grid mapping (io/grid_mapping.h) to the grids of a file as it is read. Internal header:
// includes OpenVDB.

#include "libvdbappear/io/grid_mapping.h"

#include <openvdb/openvdb.h>

#include <string>

namespace vdbappear {

// The grids with each rule's role made from its sources: the sources are consumed (removed), a
// grid already named like the role is replaced, and the rest are kept in order. Each made grid
// passes validateGrid. Throws MediumError naming `source` and the rule: a missing source grid, a
// source of the wrong value type, three sources with different transforms, values the role does
// not allow.
openvdb::GridPtrVec applyGridMapping(const openvdb::GridPtrVec& grids, const GridMapping& mapping,
                                     const std::string& source);

}  // namespace vdbappear
