#pragma once
// Triangle meshes from OBJ, PLY and the other formats Assimp reads, flattened into world-space
// triangles (node transforms applied, polygons triangulated).

#include "libvdbappear/render/area_light.h"  // Triangle

#include <string>
#include <vector>

namespace vdbappear {

// Throws std::runtime_error naming the file when it cannot be read or holds no triangle.
std::vector<Triangle> readMesh(const std::string& path);

}  // namespace vdbappear
