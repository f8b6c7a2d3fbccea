#include "libvdbappear/io/grid_mapping.h"

#include "libvdbappear/io/medium.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

// The roles a mapping may fill: the base grids of docs/medium.md §3, and the emission of §3b.
constexpr std::array<const char*, 6> kRoles = {grid_names::kDensity,     grid_names::kAlbedo, grid_names::kSggxDiag,
                                               grid_names::kSggxOffdiag, grid_names::kHgG,   grid_names::kEmission};

// Roles of RGB colour: made from one vec3s grid, one float grid (grey) or three float grids.
bool isColourRole(const std::string& role) { return role == grid_names::kAlbedo || role == grid_names::kEmission; }

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find(separator, start)) != std::string::npos; start = end + 1)
    parts.push_back(text.substr(start, end - start));
  parts.push_back(text.substr(start));
  return parts;
}

double parseScale(const std::string& text, const std::string& rule) {
  std::size_t used = 0;
  double scale = 0;
  try {
    scale = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(scale) || !(scale > 0))
    throw std::invalid_argument(fmt::format("'{}': the scale '{}' is not a number > 0", rule, text));
  return scale;
}

constexpr const char* kBlackbodyPrefix = "blackbody:";

// emission=blackbody:GRID[:KELVIN[:INTENSITY]] (medium/blackbody.h).
GridRule parseBlackbodyRule(const std::string& text, const std::string& parameters) {
  GridRule rule;
  rule.role = grid_names::kEmission;
  rule.blackbody = true;
  const std::vector<std::string> parts = split(parameters, ':');
  if (parts.size() > 3 || parts[0].empty() || parts[0].find_first_of(",/") != std::string::npos)
    throw std::invalid_argument(fmt::format("'{}': expected emission=blackbody:GRID[:KELVIN[:INTENSITY]]", text));
  rule.sources = {parts[0]};
  if (parts.size() > 1) rule.kelvin = parseScale(parts[1], text);
  if (parts.size() > 2) {
    rule.intensity = parseScale(parts[2], text);
    if (rule.intensity > 1)
      throw std::invalid_argument(fmt::format("'{}': the blackbody intensity '{}' is not in (0, 1]", text, parts[2]));
  }
  return rule;
}

}  // namespace

GridRule parseGridRule(const std::string& text) {
  const std::string blackbody = std::string(grid_names::kEmission) + "=" + kBlackbodyPrefix;
  if (text.rfind(blackbody, 0) == 0) return parseBlackbodyRule(text, text.substr(blackbody.size()));
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos)
    throw std::invalid_argument(fmt::format("'{}': expected ROLE=GRID[,GRID,GRID][/DIVISOR][:SCALE]", text));
  GridRule rule;
  rule.role = text.substr(0, equals);
  if (std::find(kRoles.begin(), kRoles.end(), rule.role) == kRoles.end())
    throw std::invalid_argument(fmt::format("'{}': '{}' is not a grid of the medium contract ({})", text, rule.role,
                                            fmt::join(kRoles, ", ")));
  std::string sources = text.substr(equals + 1);
  if (const std::size_t colon = sources.rfind(':'); colon != std::string::npos) {
    rule.scale = parseScale(sources.substr(colon + 1), text);
    sources.resize(colon);
  }
  if (const std::size_t slash = sources.find('/'); slash != std::string::npos) {
    rule.divisor = sources.substr(slash + 1);
    sources.resize(slash);
    if (rule.role != grid_names::kAlbedo)
      throw std::invalid_argument(fmt::format("'{}': only albedo is divided by a grid (a colour times density)", text));
    if (rule.divisor.empty() || rule.divisor.find_first_of("/,") != std::string::npos)
      throw std::invalid_argument(fmt::format("'{}': expected one grid name after '/'", text));
  }
  rule.sources = split(sources, ',');
  for (const std::string& source : rule.sources)
    if (source.empty()) throw std::invalid_argument(fmt::format("'{}': a grid name is empty", text));
  if (rule.sources.size() == 3 && !isColourRole(rule.role))
    throw std::invalid_argument(fmt::format("'{}': only albedo and emission are made from three grids (R, G, B)", text));
  if (rule.sources.size() != 1 && rule.sources.size() != 3)
    throw std::invalid_argument(
        fmt::format("'{}': expected one grid, or three for albedo and emission (R, G, B)", text));
  return rule;
}

std::string gridRuleText(const GridRule& rule) {
  if (rule.blackbody) {
    std::string text = fmt::format("{}={}{}", rule.role, kBlackbodyPrefix, rule.sources.front());
    if (rule.kelvin != 1000 || rule.intensity != 1) text += fmt::format(":{}", rule.kelvin);
    if (rule.intensity != 1) text += fmt::format(":{}", rule.intensity);
    return text;
  }
  std::string text = fmt::format("{}={}", rule.role, fmt::join(rule.sources, ","));
  if (!rule.divisor.empty()) text += "/" + rule.divisor;
  if (rule.scale != 1) text += fmt::format(":{}", rule.scale);
  return text;
}

GridPreset parseGridPreset(const std::string& name) {
  for (GridPreset preset : {GridPreset::kAuto, GridPreset::kNone, GridPreset::kBlender, GridPreset::kHoudini})
    if (name == gridPresetName(preset)) return preset;
  throw std::invalid_argument(fmt::format("'{}': expected auto, blender, houdini or none", name));
}

const char* gridPresetName(GridPreset preset) {
  switch (preset) {
    case GridPreset::kAuto: return "auto";
    case GridPreset::kNone: return "none";
    case GridPreset::kBlender: return "blender";
    case GridPreset::kHoudini: return "houdini";
  }
  return "?";
}

void addGridRule(GridMapping& mapping, GridRule rule) {
  for (const GridRule& existing : mapping.rules)
    if (existing.role == rule.role)
      throw std::invalid_argument(fmt::format("'{}': {} is already mapped ('{}')", gridRuleText(rule), rule.role,
                                              gridRuleText(existing)));
  mapping.rules.push_back(std::move(rule));
}

}  // namespace vdbappear
