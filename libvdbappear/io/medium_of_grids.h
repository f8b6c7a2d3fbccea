#pragma once
// The reader's steps (io/medium_file.cpp) for code that reads a file's grids its own way: in slabs
// (io/medium_slabs.h). Internal header: includes OpenVDB.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace vdbappear {

// Every grid has a name, and no name appears twice; MediumError names `source` otherwise.
void checkGridNames(std::vector<std::string> names, const std::string& source);

// The medium of grids that each passed validateGrid: mapped, sorted into roles, checked across grids.
MediumPtr mediumOfGrids(openvdb::GridPtrVec grids, openvdb::MetaMap::Ptr metadata, const GridMapping& mapping,
                        const std::string& source);

}  // namespace vdbappear
