#pragma once
// Writing grids to a VDB file or stream, shared by the library's file formats. OpenVDB-heavy:
// included only by the io/ sources.

#include <openvdb/openvdb.h>

#include <string>

namespace vdbappear {

// path "-": a VDB stream on stdout. Otherwise a temporary file next to `path`, written through a
// checked stream (a full disk is an error, not a truncated file) and renamed into place.
// Throws MediumError naming the path.
void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata);

}  // namespace vdbappear
