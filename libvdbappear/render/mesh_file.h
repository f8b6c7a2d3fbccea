#pragma once
// Triangle meshes from OBJ, PLY and the other formats Assimp reads, flattened into world-space
// triangles (node transforms applied, polygons triangulated).

#include "libvdbappear/render/area_light.h"  // Triangle
#include "libvdbappear/surface/mesh_shell.h"   // UvTriangle

#include <string>
#include <vector>

namespace vdbappear {

// Throws std::runtime_error naming the file when it cannot be read or holds no triangle.
std::vector<Triangle> readMesh(const std::string& path);

// The triangles with their texture coordinates (the first UV channel) and shading normals (the
// file's, or smooth ones where it has none), for a displacement map over the mesh
// (surface/mesh_shell.h). Throws std::runtime_error naming the file when it has no UVs.
std::vector<UvTriangle> readUvMesh(const std::string& path);

}  // namespace vdbappear
