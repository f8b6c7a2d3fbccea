#pragma once
// Placement of a downsampled medium (docs/medium.md): coarse voxel I holds fine voxels
// F*I .. F*I+F-1 on each axis, so its centre sits at fine index F*I + (F-1)/2.

#include <openvdb/math/Transform.h>

#include <string>

namespace vdbappear {

// The transform of the coarse grid; throws MediumError (naming `source`) unless `fine` is linear.
openvdb::math::Transform::Ptr coarseTransform(const openvdb::math::Transform& fine, int factor,
                                              const std::string& source);

}  // namespace vdbappear
