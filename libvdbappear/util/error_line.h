#pragma once
// What a tool prints of an error: one line of readable length. A message quoting bytes of a corrupt
// file can hold line breaks, control characters or, from OpenVDB's reader, a blank-filled grid type
// of a gigabyte (tests/fuzz/findings/README.md). Light header.

#include <cstddef>
#include <string>
#include <string_view>

namespace vdbappear {

// Line breaks, tabs and other control characters become spaces; runs of spaces shrink to one;
// a message longer than max_chars keeps its start and end around "[... N characters cut ...]".
std::string errorLine(std::string_view what, std::size_t max_chars = 2000);

}  // namespace vdbappear
