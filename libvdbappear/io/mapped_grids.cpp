#include "libvdbappear/io/mapped_grids.h"

#include "libvdbappear/io/grid_presets.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/io/set_active_values.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <array>
#include <set>
#include <vector>

namespace vdbappear {

namespace {

openvdb::GridBase::Ptr findGrid(const openvdb::GridPtrVec& grids, const std::string& name) {
  const auto it = std::find_if(grids.begin(), grids.end(), [&](const auto& grid) { return grid->getName() == name; });
  return it == grids.end() ? nullptr : *it;
}

// The error prefix of a rule: "in.vdb: --grid albedo=Cd".
std::string ruleContext(const GridRule& rule, const std::string& source) {
  return fmt::format("{}: --grid {}", source, gridRuleText(rule));
}

template <typename GridT>
typename GridT::Ptr sourceOfType(const openvdb::GridPtrVec& grids, const GridRule& rule, const std::string& name,
                                 const std::string& source,
                                 const std::string& expected = openvdb::typeNameAsString<typename GridT::ValueType>()) {
  const openvdb::GridBase::Ptr grid = findGrid(grids, name);
  if (!grid) {
    std::vector<std::string> sorted;
    for (const auto& g : grids) sorted.push_back(g->getName());
    std::sort(sorted.begin(), sorted.end());
    std::string names;
    for (const auto& n : sorted) names += (names.empty() ? "" : ", ") + n;
    throw MediumError(fmt::format("{}: no grid named '{}' (the file has {})", ruleContext(rule, source), name, names));
  }
  auto typed = openvdb::gridPtrCast<GridT>(grid);
  if (!typed)
    throw MediumError(fmt::format("{}: grid '{}' holds {} values, expected {}", ruleContext(rule, source), name,
                                  grid->valueType(), expected));
  return typed;
}

// A copy of `grid` named `role`, every value (background included) times `scale`.
template <typename GridT>
typename GridT::Ptr scaledCopy(const GridT& grid, const std::string& role, double scale) {
  typename GridT::Ptr copy = grid.deepCopy();
  copy->setName(role);
  if (scale != 1) {
    using ValueT = typename GridT::ValueType;
    const auto factor = static_cast<float>(scale);
    openvdb::tree::LeafManager<typename GridT::TreeType> leaves(copy->tree());  // every value, leaf by leaf
    leaves.foreach([factor](typename GridT::TreeType::LeafNodeType& leaf, std::size_t) {
      for (auto v = leaf.beginValueAll(); v; ++v) v.setValue(ValueT(*v * factor));
    });
    auto tile = copy->tree().beginValueAll();
    tile.setMaxDepth(GridT::TreeType::ValueAllIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) tile.setValue(ValueT(*tile * factor));
    // The inactive values are scaled above; the root's background is not one of them.
    copy->tree().root().setBackground(ValueT(copy->background() * factor), /*updateChildNodes=*/false);
  }
  return copy;
}

// Grids combined voxel by voxel (a rule's channels, a value and its divisor) share one transform.
void requireSameTransform(const openvdb::GridBase& a, const std::string& a_name, const openvdb::GridBase& b,
                          const std::string& b_name, const GridRule& rule, const std::string& source) {
  if (a.transform() != b.transform())
    throw MediumError(fmt::format("{}: grids '{}' and '{}' have different transforms", ruleContext(rule, source),
                                  a_name, b_name));
}

// Three float grids as the R, G, B of one Vec3 grid on the union of their active voxels.
openvdb::Vec3SGrid::Ptr rgbOfThree(const std::array<openvdb::FloatGrid::Ptr, 3>& channels, const GridRule& rule,
                                   const std::string& source) {
  for (int c = 1; c < 3; ++c)
    requireSameTransform(*channels[0], channels[0]->getName(), *channels[c], channels[c]->getName(), rule, source);
  const auto factor = static_cast<float>(rule.scale);
  auto rgb = openvdb::Vec3SGrid::create(openvdb::Vec3s(channels[0]->background(), channels[1]->background(),
                                                       channels[2]->background()) * factor);
  rgb->setName(rule.role);
  rgb->setTransform(channels[0]->transform().copy());
  for (const auto& channel : channels) rgb->tree().topologyUnion(channel->tree());
  setActiveValues(*rgb, [&](const openvdb::Coord& ijk, const openvdb::Vec3s&) {  // a tile: the channels' tiles share ijk
    return openvdb::Vec3s(channels[0]->tree().getValue(ijk), channels[1]->tree().getValue(ijk),
                          channels[2]->tree().getValue(ijk)) *
           factor;
  });
  return rgb;
}

// emission=blackbody:GRID: the temperature attribute in kelvin (KELVIN per unit, as Principled
// Volume's Temperature input scales it), as the contract's blackbody_temperature grid with the
// rule's Blackbody Intensity in its metadata (docs/medium.md §3b). The light is made from it at each
// lookup, after interpolation, as Cycles does.
openvdb::FloatGrid::Ptr blackbodyTemperature(const openvdb::FloatGrid& temperature, const GridRule& rule,
                                             const std::string& source) {
  for (auto v = temperature.cbeginValueOn(); v; ++v)  // tree order: the same culprit at every run
    if (!(*v >= 0 && *v <= FLT_MAX))
      throw MediumError(fmt::format("{}: grid '{}': temperature {} is {} at {} ({},{},{})", ruleContext(rule, source),
                                    temperature.getName(), *v, std::isfinite(*v) ? "negative" : "not finite",
                                    v.isVoxelValue() ? "voxel" : "tile", v.getCoord().x(), v.getCoord().y(),
                                    v.getCoord().z()));
  auto kelvin = scaledCopy(temperature, grid_names::kBlackbodyTemperature, rule.kelvin);
  kelvin->insertMeta(metadata_names::kBlackbodyIntensity, openvdb::FloatMetadata(float(rule.intensity)));
  return kelvin;
}

openvdb::GridBase::Ptr undividedGrid(const openvdb::GridPtrVec& grids, const GridRule& rule, const std::string& source) {
  namespace names = grid_names;
  if (rule.blackbody)
    return blackbodyTemperature(*sourceOfType<openvdb::FloatGrid>(grids, rule, rule.sources.front(), source), rule,
                                source);
  if (rule.sources.size() == 3) {
    std::array<openvdb::FloatGrid::Ptr, 3> channels;
    for (int c = 0; c < 3; ++c) channels[c] = sourceOfType<openvdb::FloatGrid>(grids, rule, rule.sources[c], source);
    return rgbOfThree(channels, rule, source);
  }
  const std::string& name = rule.sources.front();
  if (rule.role == names::kSggxDiag || rule.role == names::kSggxOffdiag)
    return scaledCopy(*sourceOfType<openvdb::Vec3SGrid>(grids, rule, name, source), rule.role, rule.scale);
  if (rule.role == names::kAlbedo || rule.role == names::kEmission) {  // grey or RGB
    const openvdb::GridBase::Ptr grid = findGrid(grids, name);
    if (auto grey = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)) return scaledCopy(*grey, rule.role, rule.scale);
    return scaledCopy(*sourceOfType<openvdb::Vec3SGrid>(grids, rule, name, source, "vec3s or float"), rule.role,
                      rule.scale);
  }
  return scaledCopy(*sourceOfType<openvdb::FloatGrid>(grids, rule, name, source), rule.role, rule.scale);
}

float clampedAlbedo(float a) { return std::clamp(a, 0.0f, 1.0f); }  // NaN stays NaN, for validation to name
openvdb::Vec3s clampedAlbedo(const openvdb::Vec3s& a) {
  return {clampedAlbedo(a[0]), clampedAlbedo(a[1]), clampedAlbedo(a[2])};
}

// `/DIVISOR`: each active value over the divisor's value at its voxel, clamped to [0, 1] (the
// ratio of two fields advected separately overshoots where the density is tiny); 1, the contract's
// albedo, where the divisor is not > 0 (no medium there). Tiles are voxelised first.
template <typename GridT>
typename GridT::Ptr dividedBy(typename GridT::Ptr grid, const openvdb::FloatGrid& divisor, const GridRule& rule,
                              const std::string& source) {
  requireSameTransform(*grid, rule.sources.front(), divisor, rule.divisor, rule, source);
  using ValueT = typename GridT::ValueType;
  grid->tree().voxelizeActiveTiles();
  setActiveValues(*grid, [&](const openvdb::Coord& ijk, const ValueT& value) {
    const float d = divisor.tree().getValue(ijk);
    return d > 0 ? ValueT(clampedAlbedo(value * (1 / d))) : ValueT(1.0f);
  });
  return grid;
}

openvdb::GridBase::Ptr madeGrid(const openvdb::GridPtrVec& grids, const GridRule& rule, const std::string& source) {
  openvdb::GridBase::Ptr made = undividedGrid(grids, rule, source);
  if (rule.divisor.empty()) return made;
  const auto divisor = sourceOfType<openvdb::FloatGrid>(grids, rule, rule.divisor, source);
  if (auto grey = openvdb::gridPtrCast<openvdb::FloatGrid>(made))
    return dividedBy<openvdb::FloatGrid>(grey, *divisor, rule, source);
  return dividedBy<openvdb::Vec3SGrid>(openvdb::gridPtrCast<openvdb::Vec3SGrid>(made), *divisor, rule, source);
}

// One read's mapping in progress: the grids made so far and the names they replace.
class GridMapper {
 public:
  GridMapper(const openvdb::GridPtrVec& grids, const std::string& source) : grids_(grids), source_(source) {}

  // Makes the rule's grid; MediumError names `made_by` where the grid breaks its role's rules.
  void apply(const GridRule& rule, const std::string& made_by) {
    openvdb::GridBase::Ptr grid = madeGrid(grids_, rule, source_);
    try {
      validateGrid(*grid, source_);
    } catch (const MediumError& e) {
      throw MediumError(fmt::format("{} (made by {})", e.what(), made_by));
    }
    made_.push_back(grid);
    result_.applied.push_back(rule);
    replaced_.insert(rule.role);
    replaced_.insert(grid->getName());  // blackbody_temperature, for emission=blackbody:...
    replaced_.insert(rule.sources.begin(), rule.sources.end());
  }

  // A preset's rule, with a note of what it read; a detected one (kAuto) whose grid breaks its
  // role's rules is left out with a note of why.
  void applyPreset(const PresetRule& p, GridPreset preset) {
    const std::string text = gridRuleText(p.rule);
    const bool detected = preset == GridPreset::kAuto;
    try {
      apply(p.rule, fmt::format("--from {}: --grid {}", gridPresetName(preset), text));
    } catch (const MediumError& e) {
      if (!detected) throw;
      std::string reason = e.what();  // "SOURCE: grid ...": the note names the source once
      if (reason.rfind(source_ + ": ", 0) == 0) reason.erase(0, source_.size() + 2);
      note(fmt::format("{}: not read as --grid {}, the grids are read as they are: {}", p.convention, text, reason));
      return;
    }
    note(fmt::format("{}: read as --grid {}{}", p.convention, text,
                     detected ? " (--from none reads the grids as they are)" : ""));
  }

  void note(const std::string& line) { result_.notes.push_back(fmt::format("{}: {}", source_, line)); }

  MappedGrids finish() {
    for (const auto& grid : grids_)
      if (!replaced_.count(grid->getName())) result_.grids.push_back(grid);
    result_.grids.insert(result_.grids.end(), made_.begin(), made_.end());
    return std::move(result_);
  }

 private:
  const openvdb::GridPtrVec& grids_;
  const std::string& source_;
  MappedGrids result_;
  openvdb::GridPtrVec made_;
  std::set<std::string> replaced_;
};

}  // namespace

MappedGrids applyGridMapping(const openvdb::GridPtrVec& grids, const GridMapping& mapping, const std::string& source) {
  GridMapper mapper(grids, source);
  for (const GridRule& rule : mapping.rules) mapper.apply(rule, "--grid " + gridRuleText(rule));
  const std::vector<PresetRule> preset = presetRules(grids, mapping.preset, mapping.rules);
  for (const PresetRule& p : preset) mapper.applyPreset(p, mapping.preset);
  const bool named = mapping.preset == GridPreset::kBlender || mapping.preset == GridPreset::kHoudini;
  std::vector<GridRule> proposed = mapping.rules;  // explicit and preset rules, applied or left out with a note
  for (const PresetRule& p : preset) proposed.push_back(p.rule);
  if (named && !mapsRole(proposed, grid_names::kAlbedo))
    mapper.note(fmt::format("--from {}: none of its colour grids ({}): the grids are read as they are",
                            gridPresetName(mapping.preset),
                            mapping.preset == GridPreset::kBlender ? "color_r, color_g, color_b; color" : "Cd"));
  if (mapping.preset != GridPreset::kNone && !mapsRole(proposed, grid_names::kEmission) &&
      isForeignFile(grids, mapping.preset))
    if (auto unread = unreadConventionGrids(grids)) mapper.note(*unread);
  return mapper.finish();
}

}  // namespace vdbappear
