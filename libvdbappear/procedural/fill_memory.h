#pragma once
// How much memory a procedural medium may take while it is made (docs/scaling.md §5): past a share
// of the budget, fillMedium makes the rest in slabs along x that wait on scratch files beside the
// output (io/spilled_medium.h), so that media larger than memory can be made. Light header.

#include <cstdint>
#include <string>

namespace vdbappear {

struct FillMemory {
  std::uint64_t budget_bytes = 0;    // 0: the whole medium in memory, however large
  std::string scratch_beside = "-";  // the output whose folder holds the scratch files ("-": the temporary folder)
};

}  // namespace vdbappear
