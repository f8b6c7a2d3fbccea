#pragma once
// How much memory this machine has, for refusing work that cannot fit before allocating it.

#include <unistd.h>

#include <algorithm>
#include <cstdint>

namespace vdbappear {

// Physical memory in bytes (0 where the system does not say).
inline double physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? double(pages) * double(page_size) : 0.0;
}

// The memory budget of a tool that works in slabs (--memory; docs/scaling.md §5) when none is given:
// a quarter of the machine's memory, at most 4 GB (16 GB assumed where the system does not say).
inline std::uint64_t defaultMemoryBudget() {
  const double machine = physicalMemoryBytes() > 0 ? physicalMemoryBytes() : 16e9;
  return std::uint64_t(std::min(machine / 4, 4e9));
}

}  // namespace vdbappear
