#pragma once
// What the tools make of a medium file (vdb_info; issue 26): each grid with its role in the medium
// contract (docs/medium.md) or why no tool reads it, the world box, the voxel size, the value ranges
// of density and albedo, and a vdb_render command line that frames the medium (under vdb_render's
// default lights a white, non-absorbing smoke shows its structure). Light header.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

struct Medium;

struct GridRole {
  std::string name, type;
  std::uint64_t active_voxels = 0;
  bool used = false;  // read by the tools (the contract names it); else `role` says why not
  std::string role;
};

struct ValueRange {
  double min = 0, max = 0, mean = 0;  // over active voxels, tiles counted by their voxels
};

struct MediumInfo {
  std::vector<GridRole> grids;
  std::vector<std::pair<std::string, std::string>> metadata;  // file metadata: name, value as text
  std::array<double, 3> voxel_size{};
  std::array<double, 3> world_min{}, world_max{};  // the density's and emission's active voxels, cells included
  std::uint64_t active_voxels = 0;                 // of the density grid
  ValueRange density;
  std::optional<std::array<ValueRange, 3>> albedo;  // per channel; none: albedo 1 everywhere
  std::optional<std::array<ValueRange, 3>> emission;  // per voxel and channel, blackbody light included; none: nothing emits (docs/medium.md §3b)
  std::string emission_convention;                    // cycles or pbrt, when the medium emits
  std::optional<ValueRange> blackbody_temperature;    // kelvin, with a blackbody_temperature grid (§3b)
  double blackbody_intensity = 1;                     // its Blackbody Intensity
  std::vector<std::string> notes;                   // what a user should know before rendering
  std::string render_command;                       // vdb_render FILE -o NAME.png --camera-... (POSIX-shell quoted)
};

// `file` is the path the command line names (it appears in render_command).
MediumInfo describeMedium(const Medium& medium, const std::string& file);

// The role of a grid name in the medium contract, or nullopt; and what a known grid of another
// program (Blender, Mantaflow, Houdini) is, for those the contract does not name.
std::optional<std::string> contractRole(const std::string& name);
std::optional<std::string> foreignGridRole(const std::string& name);

}  // namespace vdbappear
