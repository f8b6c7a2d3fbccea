#pragma once
// The pages of memory-mapped files that this process has touched count in its resident memory until
// they are given back; OpenVDB's delayed loading maps files (the scratch files of io/spilled_medium.h).

#include <string>
#include <vector>

namespace vdbappear {

// Gives back the pages of every mapping of these files (found in /proc/self/maps, a file removed
// since it was mapped included): what is read again later faults its pages in again, from the page
// cache. Does nothing where a file or /proc is missing.
void releaseMappedPages(const std::vector<std::string>& paths);

}  // namespace vdbappear
