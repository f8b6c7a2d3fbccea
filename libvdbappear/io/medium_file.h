#pragma once
// Reading and writing media (docs/medium.md) as VDB files or streams. Light header: tools include
// it without pulling in OpenVDB; the Medium itself is defined in io/medium.h.

#include "libvdbappear/io/grid_mapping.h"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

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
// What the reader decided for the user as it read `medium` (what a preset mapped), one line each:
// Medium::read_notes, for tools that do not include OpenVDB.
const std::vector<std::string>& readNotes(const Medium& medium);

// Validates the medium (a tool never writes what the tools would refuse to read; a medium made in
// parts, io/spilled_medium.h, was validated part by part and is not read whole again), appends
// history_line to its `history` metadata, stamps `schema`, and writes it. A file is written to a
// temporary name in the same folder, checked, and renamed when complete, so OUT is either the old
// file or the whole new one. path "-" writes a VDB stream to stdout.
void writeMedium(const Medium& medium, const std::string& path, const std::string& history_line);

// Fails early (MediumError) when `path` could not be written: stdout ("-") is a terminal, the folder
// does not exist or is not writable, or the path is a folder. Tools call it before any work.
void checkWritable(const std::string& path);

}  // namespace vdbappear
