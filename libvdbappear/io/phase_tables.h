#pragma once
// Tabulated phase functions on disk (docs/medium.md §6): table t is row y = t of the `phase_table`
// grid, bin b at index (b, t, 0), k = metadata `phase_table_bins` (else the grid's x extent). Light
// header.

#include <string>
#include <vector>

namespace vdbappear {

struct Medium;

inline constexpr const char* kPhaseTableBinsMetadata = "phase_table_bins";

// The medium's tables as stored (not normalised); empty when it has no `phase_table`. Throws
// MediumError naming the file and the grid when the layout is not (bin >= 0, id >= 0, 0).
std::vector<std::vector<double>> readPhaseTables(const Medium& medium);

// Replaces the medium's `phase_table` grid (given the medium's transform) and sets
// `phase_table_bins`; every table must have the same number of bins.
void setPhaseTables(Medium& medium, const std::vector<std::vector<double>>& tables);

}  // namespace vdbappear
