#pragma once
// Polygonal lights for vdb_sh_lightgrid (docs/sh_lightgrid.md):
//   {"lights": [{"vertices": [[x,y,z], ...], "radiance": [r,g,b] | L, "two_sided": false}, ...]}
// Light header.

#include "libvdbappear/lightgrid/polygon_light.h"

#include <string>
#include <vector>

namespace vdbappear {

// Throws MediumError "FILE: lights[K]: what is wrong". path "-" reads stdin.
std::vector<PolygonLight> readLightList(const std::string& path);

// The bounds of all vertices.
void lightBounds(const std::vector<PolygonLight>& lights, Vec3* lo, Vec3* hi);

}  // namespace vdbappear
