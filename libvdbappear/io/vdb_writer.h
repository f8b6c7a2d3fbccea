#pragma once
// Writing grids to a VDB file or stream, shared by the library's file formats. OpenVDB-heavy:
// included only by the io/ sources.

#include <openvdb/openvdb.h>

#include <functional>
#include <ostream>
#include <string>

namespace vdbappear {

// path "-": a VDB stream on stdout. Otherwise a temporary file next to `path`, written through a
// checked stream (a full disk is an error, not a truncated file) and renamed into place.
// Throws MediumError naming the path.
void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata);

// Writes a VDB file or stream as writeVdb does (a temporary file renamed into place, or stdout for
// "-"), with `write` making its bytes on a stream that is seekable for a file, not for stdout.
using VdbStreamWriter = std::function<void(std::ostream& os, bool seekable)>;
void writeVdbWith(const std::string& path, const VdbStreamWriter& write);

// A scratch file, written where it is (no temporary name, no rename) and quickly: leaf values are
// not compressed beyond their active masks. Throws MediumError naming `file`.
void writeScratchVdb(const std::string& file, const openvdb::GridCPtrVec& grids);

// The same on a stream (not seekable: no grid offsets), with file-level metadata. Throws what
// OpenVDB's writer throws.
void writeScratchVdbStream(std::ostream& os, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata);

}  // namespace vdbappear
