#pragma once
// Provenance: the line each tool appends to a medium's `history` metadata (docs/medium.md, section 8).

#include <string>

namespace vdbappear {

// "vdb_tool 0.1.0: vdb_tool --flag value IN OUT": tool name, version and the command line, the
// first word replaced by the tool name and arguments shell-quoted where needed.
std::string historyLine(const std::string& tool, int argc, const char* const* argv);

// arg as one word of a POSIX shell: as it is when it holds only safe characters, else in single quotes.
std::string shellQuote(const std::string& arg);

}  // namespace vdbappear
