#pragma once
// Foreign grid names read as the medium contract's grids (docs/medium.md §12): a Houdini file's
// `Cd` as `albedo`, a Mantaflow cache's `color_r`, `color_g`, `color_b` as the three channels of
// `albedo`, a density scaled by 0.5. One mapping, applied as a file is read, serves every tool
// (`--grid` in each tool's flags). Light header: no OpenVDB.

#include <string>
#include <vector>

namespace vdbappear {

// The contract grid `role` made from the file's grids `sources`, times `scale`: one grid of the
// role's type (albedo: a float grid is grey), or three float grids as R, G, B (albedo only).
// With a `divisor` (albedo only), each voxel is divided by that float grid's value there: a colour
// premultiplied by the density, as Mantaflow writes it (docs/medium.md §12).
// Or (emission only, `blackbody`) the one source is a temperature attribute, read as the contract's
// blackbody_temperature (kelvin: `kelvin` per unit of the grid, Principled Volume's Temperature) with
// Blackbody Intensity `intensity` in its metadata, whose light Blender Cycles' Principled Volume
// makes (medium/blackbody.h, docs/medium.md §3b): "emission=blackbody:temperature[:K[:I]]".
struct GridRule {
  std::string role;
  std::vector<std::string> sources;
  std::string divisor;  // empty: none
  double scale = 1;
  bool blackbody = false;
  double kelvin = 1000, intensity = 1;
};

// The grid conventions of other programs (docs/medium.md §12, io/grid_presets.h): kBlender reads
// a Mantaflow smoke cache's colour or a Volume object's `color` as the albedo, kHoudini a `Cd`;
// kAuto detects them from the grids of a file that has no albedo grid, and the reader says what it
// mapped (Medium::read_notes); kNone reads the grids as they are.
enum class GridPreset { kAuto, kNone, kBlender, kHoudini };

// The rules of one read, at most one per role, and a preset for the roles they leave. No rules and
// kNone: the grids are read as they are.
struct GridMapping {
  std::vector<GridRule> rules;
  GridPreset preset = GridPreset::kAuto;
};

// "auto", "none", "blender", "houdini"; throws std::invalid_argument naming the choices.
GridPreset parseGridPreset(const std::string& name);
const char* gridPresetName(GridPreset preset);

// Parses ROLE=GRID[,GRID,GRID][/DIVISOR][:SCALE] ("albedo=Cd", "albedo=color_r,color_g,color_b",
// "albedo=color_r,color_g,color_b/density", "density=density:0.5") and
// emission=blackbody:GRID[:KELVIN[:INTENSITY]]. Throws std::invalid_argument with the reason.
GridRule parseGridRule(const std::string& text);

// The rule as parseGridRule reads it back.
std::string gridRuleText(const GridRule& rule);

// Adds a rule; throws std::invalid_argument if its role has one already.
void addGridRule(GridMapping& mapping, GridRule rule);

}  // namespace vdbappear
