#pragma once
// The MediumError message of reading a prefiltered displacement map's manifest, or "" when it reads
// (prefilter/prefiltered_surface_file.h).

#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/util/error.h"

#include <string>

namespace vdbappear::test {

inline std::string readPrefilteredSurfaceError(const std::string& manifest_path) {
  try {
    readPrefilteredSurface(manifest_path);
  } catch (const MediumError& e) {
    return e.what();
  }
  return "";
}

}  // namespace vdbappear::test
