#include "libvdbappear/io/grid_presets.h"

#include "libvdbappear/io/medium.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace vdbappear {

namespace {

template <typename GridT>
bool hasGrid(const openvdb::GridPtrVec& grids, const std::string& name) {
  return std::any_of(grids.begin(), grids.end(), [&](const openvdb::GridBase::Ptr& grid) {
    return grid->getName() == name && grid->isType<GridT>();
  });
}

bool hasAnyGrid(const openvdb::GridPtrVec& grids, const std::string& name) {
  return std::any_of(grids.begin(), grids.end(), [&](const auto& grid) { return grid->getName() == name; });
}

std::optional<PresetRule> mantaflowColour(const openvdb::GridPtrVec& grids) {
  for (const char* name : {"color_r", "color_g", "color_b", grid_names::kDensity})
    if (!hasGrid<openvdb::FloatGrid>(grids, name)) return std::nullopt;
  return PresetRule{parseGridRule("albedo=color_r,color_g,color_b/density"), "Blender's smoke cache (Mantaflow)"};
}

std::optional<PresetRule> volumeObjectColour(const openvdb::GridPtrVec& grids) {
  if (!hasGrid<openvdb::Vec3SGrid>(grids, "color")) return std::nullopt;
  return PresetRule{parseGridRule("albedo=color"), "Blender's Volume object"};
}

std::optional<PresetRule> houdiniColour(const openvdb::GridPtrVec& grids) {
  if (!hasGrid<openvdb::Vec3SGrid>(grids, "Cd")) return std::nullopt;
  return PresetRule{parseGridRule("albedo=Cd"), "Houdini's Cd"};
}

std::optional<PresetRule> albedoRule(const openvdb::GridPtrVec& grids, GridPreset preset) {
  switch (preset) {
    case GridPreset::kBlender:
      if (auto rule = mantaflowColour(grids)) return rule;
      return volumeObjectColour(grids);
    case GridPreset::kHoudini: return houdiniColour(grids);
    case GridPreset::kAuto:
      if (hasAnyGrid(grids, grid_names::kAlbedo)) return std::nullopt;  // a medium of the contract
      if (auto rule = mantaflowColour(grids)) return rule;
      if (auto rule = houdiniColour(grids)) return rule;
      return volumeObjectColour(grids);
    case GridPreset::kNone: break;
  }
  return std::nullopt;
}

// Blender's fire: a float `temperature` (a Mantaflow cache's, which Cycles reads on a Volume object
// by that name) read as Quick Smoke's fire material reads it: Principled Volume with Blackbody
// Intensity 1 and Temperature 1000 K, so 1000 K per unit of the grid (docs/medium.md §12). Only in a
// fire, one whose `flame` grid has voxels: Mantaflow writes `temperature` (its heat) for smoke too,
// whose Quick Smoke material has Blackbody Intensity 0.
std::optional<PresetRule> blenderFire(const openvdb::GridPtrVec& grids) {
  if (!hasGrid<openvdb::FloatGrid>(grids, "temperature") || hasAnyGrid(grids, grid_names::kEmission)) return std::nullopt;
  const bool burns = std::any_of(grids.begin(), grids.end(), [](const openvdb::GridBase::Ptr& grid) {
    return grid->getName() == "flame" && grid->isType<openvdb::FloatGrid>() && grid->activeVoxelCount() > 0;
  });
  if (!burns) return std::nullopt;
  return PresetRule{parseGridRule("emission=blackbody:temperature"),
                    "Blender's fire (Quick Smoke's Principled Volume: blackbody at 1000 K per unit of 'temperature')"};
}

std::optional<PresetRule> emissionRule(const openvdb::GridPtrVec& grids, GridPreset preset) {
  switch (preset) {
    case GridPreset::kBlender: return blenderFire(grids);
    case GridPreset::kAuto:
      if (hasAnyGrid(grids, grid_names::kAlbedo)) return std::nullopt;  // a medium of the contract
      if (hasAnyGrid(grids, "Cd") || hasAnyGrid(grids, "vel")) return std::nullopt;  // Houdini's names: not Blender's fire
      return blenderFire(grids);
    case GridPreset::kHoudini:  // Houdini's pyro shaders map temperature through ramps of their own
    case GridPreset::kNone: break;
  }
  return std::nullopt;
}

}  // namespace

bool mapsRole(const std::vector<GridRule>& rules, const std::string& role) {
  return std::any_of(rules.begin(), rules.end(), [&role](const GridRule& rule) { return rule.role == role; });
}

std::vector<PresetRule> presetRules(const openvdb::GridPtrVec& grids, GridPreset preset,
                                    const std::vector<GridRule>& explicit_rules) {
  std::vector<PresetRule> rules;
  if (!mapsRole(explicit_rules, grid_names::kAlbedo))
    if (auto rule = albedoRule(grids, preset)) rules.push_back(std::move(*rule));
  if (!mapsRole(explicit_rules, grid_names::kEmission))
    if (auto rule = emissionRule(grids, preset)) rules.push_back(std::move(*rule));
  return rules;
}

bool isForeignFile(const openvdb::GridPtrVec& grids, GridPreset preset) {
  if (preset == GridPreset::kBlender || preset == GridPreset::kHoudini) return true;
  return preset == GridPreset::kAuto && !hasAnyGrid(grids, grid_names::kAlbedo);
}

std::optional<std::string> unreadConventionGrids(const openvdb::GridPtrVec& grids) {
  std::vector<std::string> names;  // the fire and heat grids that hold voxels
  for (const char* name : {"flame", "temperature", "heat"})
    if (std::any_of(grids.begin(), grids.end(), [name](const auto& g) { return g->getName() == name && g->activeVoxelCount() > 0; }))
      names.push_back(name);
  if (names.empty()) return std::nullopt;
  const bool temperature = std::find(names.begin(), names.end(), "temperature") != names.end();
  const std::string how = temperature ? "--grid emission=blackbody:temperature reads it as Cycles' blackbody light"
                                      : fmt::format("--grid emission={}:STRENGTH reads it as light per unit length", names.front());
  std::vector<std::string> quoted;
  for (const std::string& name : names) quoted.push_back(fmt::format("'{}'", name));
  return fmt::format("{} {} fire or heat, not read as light: {} (docs/medium.md section 3b)", fmt::join(quoted, ", "),
                     names.size() == 1 ? "holds" : "hold", how);
}

}  // namespace vdbappear
