#pragma once
// The grid conventions of Blender and Houdini as grid rules (docs/medium.md §12), chosen for the
// grids a file has. Internal header: includes OpenVDB.
//
// - Blender, smoke cache (Mantaflow): float `color_r`, `color_g`, `color_b` hold colour times
//   density; albedo=color_r,color_g,color_b/density divides them back. Cycles' Principled Volume
//   scatters with density x colour and absorbs density x (1 - colour): the colour is the albedo.
// - Blender, Volume object: a vec3s `color`, the same colour undivided: albedo=color.
// - Houdini: a vec3s `Cd`: albedo=Cd.
// - Blender, fire: a float `temperature`: emission=blackbody:temperature, Quick Smoke's fire material
//   (Principled Volume, Blackbody Intensity 1, Temperature 1000 K), when its `flame` has voxels;
//   detected (kAuto) only in a file without Houdini's `Cd` or `vel`.
// Every convention names its density `density`, the contract's own name.

#include "libvdbappear/io/grid_mapping.h"

#include <openvdb/openvdb.h>

#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

// A rule of a preset and the convention it reads ("Blender's smoke cache (Mantaflow)").
struct PresetRule {
  GridRule rule;
  std::string convention;
};

// Does one of `rules` make `role` (the albedo, the emission)? Then no preset does.
bool mapsRole(const std::vector<GridRule>& rules, const std::string& role);

// The rules of `preset` that `grids` has the grids for, for the roles `explicit_rules` leave:
// kBlender the smoke cache's colour, else a Volume object's, and its fire; kHoudini `Cd`; kAuto the
// first colour of these the file has and Blender's fire, and none when it has an `albedo` grid
// already; kNone none.
std::vector<PresetRule> presetRules(const openvdb::GridPtrVec& grids, GridPreset preset,
                                    const std::vector<GridRule>& explicit_rules);

// A file of another program's: one without an albedo grid (kAuto), or any under a named preset.
bool isForeignFile(const openvdb::GridPtrVec& grids, GridPreset preset);

// The grids of Blender's and Houdini's conventions that no rule reads (`flame`, `temperature`,
// `heat`: emission), named in a note; nullopt if the file has none.
std::optional<std::string> unreadConventionGrids(const openvdb::GridPtrVec& grids);

}  // namespace vdbappear
