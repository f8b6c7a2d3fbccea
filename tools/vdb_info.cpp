// vdb_info: what the tools make of a medium file (docs/medium.md; issue 26), like OpenVDB's
// vdb_print for its own tools: grids used and not read, and why; box, voxel size, value ranges; a
// vdb_render command line that frames it.
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_info.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <algorithm>

#include <iostream>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_info";

constexpr const char* kExamples = R"(Examples:
  vdb_info smoke.vdb                      grids, box, ranges and a render command that shows it
  vdb_info --json smoke.vdb | jq .render_command
  vdb_info pyro.vdb --from none           the file's grids as they are, no colour detected
  vdb_make_medium cloud -o - | vdb_info -
Reads the file as every tool does: a file the tools refuse gets the same one-line error here.)";

nlohmann::json rangeJson(const ValueRange& r) { return {{"min", r.min}, {"max", r.max}, {"mean", r.mean}}; }

nlohmann::json infoJson(const MediumInfo& info, const std::string& file) {
  nlohmann::json grids = nlohmann::json::array(), metadata = nlohmann::json::object();
  for (const GridRole& g : info.grids)
    grids.push_back({{"name", g.name}, {"type", g.type}, {"active_voxels", g.active_voxels}, {"used", g.used}, {"role", g.role}});
  for (const auto& [name, value] : info.metadata) metadata[name] = value;
  nlohmann::json albedo = nullptr;
  if (info.albedo) albedo = {rangeJson((*info.albedo)[0]), rangeJson((*info.albedo)[1]), rangeJson((*info.albedo)[2])};
  nlohmann::json emission = nullptr;
  if (info.emission)
    emission = {{"convention", info.emission_convention},
                {"channels", {rangeJson((*info.emission)[0]), rangeJson((*info.emission)[1]), rangeJson((*info.emission)[2])}}};
  if (info.blackbody_temperature)
    emission["blackbody"] = {{"kelvin", rangeJson(*info.blackbody_temperature)}, {"intensity", info.blackbody_intensity}};
  return {{"file", file}, {"tool", kTool}, {"version", kVersion}, {"grids", grids}, {"metadata", metadata},
          {"voxel_size", info.voxel_size}, {"world_box", {{"min", info.world_min}, {"max", info.world_max}}},
          {"active_voxels", info.active_voxels}, {"density", rangeJson(info.density)}, {"albedo", albedo},
          {"emission", emission}, {"notes", info.notes}, {"render_command", info.render_command}};
}

std::string rangeText(const ValueRange& r) { return fmt::format("{:.4g} .. {:.4g}, mean {:.4g}", r.min, r.max, r.mean); }

void printInfo(const MediumInfo& info, const std::string& file) {
  fmt::print("{}\n", file);
  std::size_t name_width = 16;  // the column fits the longest name (blackbody_temperature)
  for (const GridRole& g : info.grids) name_width = std::max(name_width, g.name.size());
  for (const GridRole& g : info.grids)
    fmt::print("  {:<{}} {:<6} {:>12} voxels  {} {}\n", g.name, name_width, g.type, g.active_voxels,
               g.used ? "used:" : "NOT READ:", g.role);
  for (const auto& [name, value] : info.metadata) fmt::print("  metadata {}: {}\n", name, value);
  fmt::print("world box   ({:.4g}, {:.4g}, {:.4g}) .. ({:.4g}, {:.4g}, {:.4g})\n", info.world_min[0], info.world_min[1],
             info.world_min[2], info.world_max[0], info.world_max[1], info.world_max[2]);
  fmt::print("voxel size  {:.4g} x {:.4g} x {:.4g}\n", info.voxel_size[0], info.voxel_size[1], info.voxel_size[2]);
  fmt::print("density     {} ({} active voxels)\n", rangeText(info.density), info.active_voxels);
  if (info.albedo)
    fmt::print("albedo      R {}; G {}; B {}\n", rangeText((*info.albedo)[0]), rangeText((*info.albedo)[1]), rangeText((*info.albedo)[2]));
  if (info.emission)
    fmt::print("emission    R {}; G {}; B {} ({})\n", rangeText((*info.emission)[0]), rangeText((*info.emission)[1]),
               rangeText((*info.emission)[2]), info.emission_convention);
  if (info.blackbody_temperature)
    fmt::print("blackbody   {} K, intensity {:.4g} (its light is in the emission above)\n",
               rangeText(*info.blackbody_temperature), info.blackbody_intensity);
  for (const std::string& note : info.notes) fmt::print("note: {}\n", note);
  fmt::print("render:\n  {}\n", info.render_command);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Says what the tools make of a medium file: each grid's role or why no tool reads it, the world box, "
               "voxel size, density, albedo and emission ranges, and a vdb_render command line that frames it.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  std::string input;
  bool json = false;
  app.add_option("MEDIUM", input, "medium (.vdb); - reads a VDB stream from stdin")->required();
  app.add_flag("--json", json, "print one JSON object instead of text");
  GridMapping mapping;
  tool::addGridMapping(app, mapping);
  return tool::run(app, argc, argv, [&] {
    const MediumPtr medium = readMedium(input, mapping);
    const MediumInfo info = describeMedium(*medium, input);
    if (json)
      std::cout << infoJson(info, input).dump(2) << "\n";
    else
      printInfo(info, input);
    return 0;
  });
}
