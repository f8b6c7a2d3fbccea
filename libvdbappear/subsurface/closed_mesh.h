#pragma once
// The dipole needs an inside: a translucent object's mesh must be closed and consistently
// oriented (every edge shared by exactly two triangles that run it in opposite directions).

#include "libvdbappear/math/triangle.h"

#include <string>
#include <vector>

namespace vdbappear {

// The triangles, turned so that their counter-clockwise normals point outward (by the sign of the
// enclosed volume; a mesh of several shells is turned as a whole, so that a hollow object's inner
// shell keeps facing its cavity). Throws std::invalid_argument "WHERE: what is wrong" for an empty mesh, a
// degenerate triangle, an open or non-manifold edge, or inconsistent orientation.
std::vector<Triangle> outwardClosedMesh(std::vector<Triangle> triangles, const std::string& where);

}  // namespace vdbappear
