#pragma once
// A single tabulated phase function in a file, for vdb_similarity --table: f(mu) on equal bins
// ascending over mu in [-1,1] (docs/medium.md §6), as
//   - JSON: an object with a "table" array (what `vdb_similarity --json` prints) or a bare array;
//   - text: numbers separated by white space or commas; '#' starts a comment.
// Light header.

#include <string>
#include <vector>

namespace vdbappear {

// Throws MediumError naming the file: missing, unreadable, not numbers, fewer than 2 values, a
// negative or non-finite value, or all zero.
std::vector<double> readPhaseTableFile(const std::string& path);

}  // namespace vdbappear
