#include "libvdbappear/io/medium_info.h"

#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/medium/emission_light.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace vdbappear {

std::optional<std::string> contractRole(const std::string& name) {
  if (name == grid_names::kDensity) return "flake density rho, the extinction scale (docs/medium.md section 3)";
  if (name == grid_names::kAlbedo) return "single-scattering albedo per RGB channel";
  if (name == grid_names::kSggxDiag || name == grid_names::kSggxOffdiag) return "SGGX matrix S: how the flakes are oriented (section 4)";
  if (name == grid_names::kHgG) return "Henyey-Greenstein asymmetry g per voxel";
  if (name == grid_names::kEmission) return "emitted light, read by metadata emission_convention (section 3b)";
  if (name == grid_names::kBlackbodyTemperature)
    return "temperature in kelvin, emitting Cycles' blackbody light, read by metadata emission_convention (section 3b)";
  if (isLobeGridName(name)) return "a lobe of the multi-lobe phase function (section 5)";
  if (name == grid_names::kCluster) return "voxel cluster of the lobe-weight factors (section 5)";
  if (name == grid_names::kPhaseId || name == grid_names::kPhaseTable) return "tabulated phase functions (section 6)";
  if (isBlockIndexedGridName(name)) return "exemplar blocks (section 6b)";
  return std::nullopt;
}

std::optional<std::string> foreignGridRole(const std::string& name) {
  if (name == "color" || name == "Cd")
    return fmt::format("colour (Blender's volume colour, Houdini's Cd), not read: the file has an albedo grid, or "
                       "--from none; where it is the single-scattering albedo, --grid albedo={} (docs/medium.md "
                       "section 12)", name);
  if (name == "color_r" || name == "color_g" || name == "color_b")
    return "a channel of a Mantaflow smoke colour, not read: the file has an albedo grid, or --from none; Mantaflow "
           "stores colour times density, and --grid albedo=color_r,color_g,color_b/density divides it back "
           "(docs/medium.md section 12)";
  if (name == "temperature")
    return "temperature (a fire's, or a smoke's heat), not read: --grid emission=blackbody:temperature reads it as "
           "Cycles' blackbody light at 1000 K per unit (docs/medium.md section 3b)";
  if (name == "flame" || name == "heat")
    return fmt::format("fire, not read: --grid emission={}:STRENGTH reads it as the medium's emission per unit "
                       "length (docs/medium.md section 3b)", name);
  if (name == "velocity" || name == "vel" || name.rfind("vel.", 0) == 0 || name.rfind("v.", 0) == 0)
    return "motion: no tool uses velocities";
  if (name == "shadow") return "Mantaflow's baked shadow: not needed (vdb_render traces its own shadows)";
  return std::nullopt;
}

namespace {

// Min, max and mean of one scalar function of the active values (tiles count as their voxels).
template <typename GridT, typename Scalar>
ValueRange rangeOf(const GridT& grid, Scalar scalar) {
  ValueRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 0};
  double sum = 0, count = 0;
  for (auto v = grid.cbeginValueOn(); v; ++v) {
    const double value = scalar(*v), n = double(v.getVoxelCount());
    range.min = std::min(range.min, value);
    range.max = std::max(range.max, value);
    sum += value * n;
    count += n;
  }
  if (count == 0) return {};
  range.mean = sum / count;
  return range;
}

std::string metadataText(const openvdb::Metadata& value) {
  std::string text = value.str();
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text.size() > 72 ? text.substr(0, 69) + "..." : text;
}

void describeGrids(const Medium& medium, MediumInfo& info) {
  for (const auto& grid : medium.grids()) {
    GridRole g{grid->getName(), grid->valueType(), grid->activeVoxelCount(), false, ""};
    if (const auto role = contractRole(g.name)) {
      g.used = true;
      g.role = *role;
    } else if (const auto foreign = foreignGridRole(g.name)) {
      g.role = *foreign;
    } else {
      g.role = "not part of the medium contract: kept and written back unchanged by the tools that write the "
               "medium; vdb_sggx_downsample drops it (docs/medium.md section 10)";
    }
    info.grids.push_back(std::move(g));
  }
}

void describeBox(const Medium& medium, MediumInfo& info) {
  const openvdb::BBoxd world = worldBoxOfCells(medium.transform(), framedVoxels(medium));
  for (int a = 0; a < 3; ++a) {
    info.voxel_size[std::size_t(a)] = medium.transform().voxelSize()[a];
    info.world_min[std::size_t(a)] = world.min()[a];
    info.world_max[std::size_t(a)] = world.max()[a];
  }
}

std::array<ValueRange, 3> channelRanges(const openvdb::Vec3SGrid& grid) {
  std::array<ValueRange, 3> ranges;
  for (int c = 0; c < 3; ++c) ranges[std::size_t(c)] = rangeOf(grid, [c](const openvdb::Vec3s& v) { return double(v[c]); });
  return ranges;
}

void describeValues(const Medium& medium, MediumInfo& info) {
  info.active_voxels = medium.density->activeVoxelCount();
  info.density = rangeOf(*medium.density, [](float v) { return double(v); });
  if (medium.albedo) {
    info.albedo = channelRanges(*medium.albedo);
  } else {
    info.notes.push_back("no 'albedo' grid: albedo 1 everywhere, a white medium that absorbs nothing; under a white sky "
                         "alone (--env 1) it vanishes into the background; vdb_render's default lights (a dim sky and "
                         "a sun) show it");
  }
  if (const auto temperature = blackbodyTemperatureGrid(medium)) {
    info.blackbody_temperature = rangeOf(*temperature, [](float v) { return double(v); });
    info.blackbody_intensity = blackbodySettings(*temperature).intensity;
  }
  if (const auto emission = voxelEmission(medium)) {
    info.emission = channelRanges(*emission);
    const EmissionConvention convention = emissionConvention(medium);
    info.emission_convention = emissionConventionName(convention);
    info.notes.push_back(convention == EmissionConvention::kCycles
                             ? "the medium emits light, per unit length whatever its density (emission_convention "
                               "cycles, docs/medium.md section 3b); vdb_render --env 0 shows its own light alone"
                             : "the medium emits light where it absorbs, sigma_a times the 'emission' radiance "
                               "(emission_convention pbrt, docs/medium.md section 3b); vdb_render --env 0 shows its "
                               "own light alone");
  }
  for (const GridRole& g : info.grids)
    if (!g.used) info.notes.push_back(fmt::format("grid '{}' is not read by any tool (see above)", g.name));
}

// A three-quarter view from the front right, above, at the distance that fits the box's bounding
// sphere in vdb_render's default 30-degree field of view. No light flags: vdb_render's default
// lights (defaultLights, render/scene_description.h) come from the camera's upper left, so that a
// terminator crosses the medium.
void suggestRender(const std::string& file, MediumInfo& info) {
  double centre[3], radius2 = 0;
  for (int a = 0; a < 3; ++a) {
    centre[a] = (info.world_min[std::size_t(a)] + info.world_max[std::size_t(a)]) / 2;
    const double half = (info.world_max[std::size_t(a)] - info.world_min[std::size_t(a)]) / 2;
    radius2 += half * half;
  }
  const double distance = std::sqrt(radius2) / std::sin(15.0 * M_PI / 180);
  const double toward[3] = {0.55, -0.75, 0.37};  // unit: from the centre to the camera
  const std::filesystem::path path(file);
  const std::string stem = file == "-" ? "medium" : path.stem().string();
  info.render_command = fmt::format(
      "vdb_render {} -o {} --camera-pos {:.4g},{:.4g},{:.4g} --camera-target {:.4g},{:.4g},{:.4g}",
      shellQuote(file), shellQuote(stem + ".png"), centre[0] + distance * toward[0], centre[1] + distance * toward[1],
      centre[2] + distance * toward[2], centre[0], centre[1], centre[2]);
}

}  // namespace

MediumInfo describeMedium(const Medium& medium, const std::string& file) {
  MediumInfo info;
  info.notes = medium.read_notes;  // what the reader mapped, first
  describeGrids(medium, info);
  for (auto m = medium.metadata.beginMeta(); m != medium.metadata.endMeta(); ++m)
    info.metadata.emplace_back(m->first, metadataText(*m->second));
  describeBox(medium, info);
  describeValues(medium, info);
  suggestRender(file, info);
  return info;
}

}  // namespace vdbappear
