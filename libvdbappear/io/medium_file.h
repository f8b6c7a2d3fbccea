#pragma once
// Reading and writing media (docs/medium.md) as VDB files or streams. Light header: tools include
// it without pulling in OpenVDB; the Medium itself is defined in io/medium.h.

#include "libvdbappear/io/grid_mapping.h"

#include <iosfwd>
#include <memory>
#include <string>

namespace vdbappear {

struct Medium;
using MediumPtr = std::shared_ptr<Medium>;

// Reads and validates a medium (io/medium_validate.h). path "-" reads a VDB stream from stdin.
// `mapping` makes contract grids of the file's foreign ones first (io/grid_mapping.h).
// Throws MediumError naming the file and the grid.
MediumPtr readMedium(const std::string& path, const GridMapping& mapping = {});
// Reads and validates a medium from a VDB stream (what readMedium("-") reads from stdin); errors
// name `source`.
MediumPtr readMediumStream(std::istream& in, const std::string& source, const GridMapping& mapping = {});

// Validates the medium (a tool never writes what the tools would refuse to read), appends
// history_line to its `history` metadata, stamps `schema`, and writes it. A file is written to a
// temporary name in the same folder, checked, and renamed when complete, so OUT is either the old
// file or the whole new one. path "-" writes a VDB stream to stdout.
void writeMedium(const Medium& medium, const std::string& path, const std::string& history_line);

// Fails early (MediumError) when `path` could not be written: stdout ("-") is a terminal, the folder
// does not exist or is not writable, or the path is a folder. Tools call it before any work.
void checkWritable(const std::string& path);

}  // namespace vdbappear
