#pragma once

#include <string>

namespace vdbappear {

// How a medium is looked up between voxel centres. kNearest (the default) is faithful to the
// voxels being compared; kTrilinear interpolates density, and density-weighted S, albedo and hg_g.
enum class Interpolation { kNearest, kTrilinear };

Interpolation parseInterpolation(const std::string& name);  // "nearest" | "trilinear"
const char* interpolationName(Interpolation interpolation);

}  // namespace vdbappear
