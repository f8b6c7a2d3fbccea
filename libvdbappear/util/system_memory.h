#pragma once
// How much memory this machine has, for refusing work that cannot fit before allocating it.

#include <unistd.h>

namespace vdbappear {

// Physical memory in bytes (0 where the system does not say).
inline double physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? double(pages) * double(page_size) : 0.0;
}

}  // namespace vdbappear
