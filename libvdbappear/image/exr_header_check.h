#pragma once
// OpenEXR headers checked before OpenEXR reads a file (docs/reliability.md §2).

#include <string>

namespace vdbappear {

// OpenEXR 3.1, the version Debian 12 ships, allocates each header attribute at the size the file
// states, up to 2 GB, before it reads the value: a 333-byte file made vdb_render take 6.9 s and
// 1.9 GB (found by the environment-map fuzz harness). Walks every attribute of every part's header
// as OpenEXR reads it and checks that each fits in the bytes the file holds; a file that is not
// OpenEXR (by its magic number) passes.
// Throws MediumError naming the file and the attribute.
void checkExrHeaders(const std::string& path);

}  // namespace vdbappear
