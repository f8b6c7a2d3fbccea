#pragma once
// Whether a rendered medium shows (issue 26): how much of the picture it covers, how it stands out
// from the background, and whether its footprint has structure beyond noise. For EXR renders with
// the alpha AOV (vdb_render --aov alpha).

#include <string>

namespace vdbappear::test {

struct Footprint {
  double coverage = 0;   // share of pixels with alpha > 0.5 (the footprint)
  double contrast = 0;   // |mean luminance inside - mean outside| / mean outside
  double structure = 0;  // relative standard deviation of the means of 4x4-pixel tiles wholly inside
};

Footprint footprintOf(const std::string& exr);

}  // namespace vdbappear::test
