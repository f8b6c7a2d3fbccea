#pragma once
// The light a medium emits per voxel (docs/medium.md §3b): its `emission` plus the blackbody light of
// its `blackbody_temperature`, both read under the file's emission_convention. Includes OpenVDB
// (through io/medium.h): for the library's .cpp files only.

#include "libvdbappear/io/medium.h"
#include "libvdbappear/medium/blackbody.h"

namespace vdbappear {

// Principled Volume's settings for a blackbody_temperature grid: the grid holds kelvin (Temperature
// 1 K per unit), Blackbody Intensity from its metadata (1 when absent), a white tint.
PrincipledBlackbody blackbodySettings(const openvdb::FloatGrid& temperature);

// The medium's blackbody_temperature grid, or null. Throws MediumError if it holds other values.
openvdb::FloatGrid::Ptr blackbodyTemperatureGrid(const Medium& medium);

// The medium's emission grid, or null. Throws MediumError if it is not RGB (the reader makes every
// emission RGB; media built in code may not).
openvdb::Vec3SGrid::Ptr emissionGrid(const Medium& medium);

// The blackbody light of each active voxel of `temperature` (medium/blackbody.h), named `emission`;
// inactive voxels emit nothing.
openvdb::Vec3SGrid::Ptr blackbodyLight(const openvdb::FloatGrid& temperature, const PrincipledBlackbody& settings);

// Each voxel's emission plus its blackbody light, active where either grid is; null where the
// medium has neither. What a nearest lookup reads, and what downsampling averages.
openvdb::Vec3SGrid::Ptr voxelEmission(const Medium& medium);

}  // namespace vdbappear
