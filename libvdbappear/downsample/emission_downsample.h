#pragma once
// The coarse `emission` grid of a downsampled medium (docs/medium.md §3b). Internal header: includes
// OpenVDB.

#include <openvdb/openvdb.h>

namespace vdbappear {

struct Medium;

// The fine light is each voxel's emission plus the blackbody light of its blackbody_temperature
// (medium/emission_light.h): the coarse medium holds light, no temperature (a T^4 law does not
// average). Coarse voxel I gathers fine voxels F*I .. F*I+F-1 per axis (docs/medium.md §2) and is
// active where one of them emits in `fine`. Under the cycles convention the value is the mean
// of the F^3 children's E (empty children count as 0): the light a coarse cell emits is that of its
// fine cells, exactly. Under pbrt's it is sum rho (1 - a) Le over the children / sum rho (1 - a) over
// every child with density, per channel (density-weighted where no child absorbs in the channel), so
// that the coarse sigma_a Le is the mean of the fine sigma_a Le, exactly when S = I.
// Null when `fine` has neither grid.
openvdb::Vec3SGrid::Ptr downsampleEmission(const Medium& fine, int factor, const openvdb::math::Transform::Ptr& coarse);

}  // namespace vdbappear
