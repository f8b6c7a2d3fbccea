#include "libvdbappear/io/medium_validate.h"

#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/io/leaf_values.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/resource_limits.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/util/error.h"

#include <openvdb/tools/Count.h>
#include <openvdb/tree/LeafManager.h>

#include <fmt/format.h>
#include <tbb/parallel_reduce.h>

#include <cfloat>
#include <cmath>
#include <optional>

namespace vdbappear {

namespace {

using openvdb::Coord;

// Finite without branches (x - x is 0 unless x is NaN or infinite), so loops vectorise.
bool isFinite(float v) { return v - v == 0.0f; }
bool isFinite(const openvdb::Vec3s& v) { return (v[0] - v[0] == 0.0f) & (v[1] - v[1] == 0.0f) & (v[2] - v[2] == 0.0f); }
template <typename T>
bool isFinite(const T&) { return true; }  // integer grids

// A problem found at a coordinate; the smallest coordinate wins, so reports are deterministic.
struct Problem {
  Coord where;
  bool voxel = true;
  std::string what;
  std::string grid;  // set where the checked tree is not the grid at fault
};

void keepFirst(std::optional<Problem>& best, std::optional<Problem> candidate) {
  if (candidate && (!best || candidate->where < best->where)) best = std::move(candidate);
}

// The first problem that `leaf_check(leaf)` finds over the leaves of `tree`, in parallel.
// LeafCheck: std::optional<Problem>(const LeafT&), reporting the leaf's first bad voxel.
template <typename TreeT, typename LeafCheck>
std::optional<Problem> firstProblemInLeaves(const TreeT& tree, const LeafCheck& leaf_check) {
  using LeafRange = typename openvdb::tree::LeafManager<const TreeT>::LeafRange;
  const openvdb::tree::LeafManager<const TreeT> leaves(tree);
  return tbb::parallel_reduce(
      leaves.leafRange(), std::optional<Problem>(),
      [&leaf_check](const LeafRange& range, std::optional<Problem> best) {
        for (auto leaf = range.begin(); leaf; ++leaf)
          if (!best || leaf->origin() < best->where) keepFirst(best, leaf_check(*leaf));
        return best;
      },
      [](std::optional<Problem> a, std::optional<Problem> b) {
        keepFirst(a, std::move(b));
        return a;
      });
}

// A rule on single values: ok(v) says whether v passes (a plain predicate, so a whole leaf buffer
// is tested in one vectorisable loop); describe(v) says what is wrong with a value that fails.
template <typename OkT, typename DescribeT>
struct ValueRule {
  OkT ok;
  DescribeT describe;
};
template <typename OkT, typename DescribeT>
ValueRule<OkT, DescribeT> valueRule(OkT ok, DescribeT describe) {
  return {ok, describe};
}

// The first active value of `tree` (voxels, then tiles) that breaks `rule`. A leaf whose whole
// buffer passes is cleared at once; otherwise its active values are scanned for the culprit
// (inactive values may hold anything).
template <typename TreeT, typename RuleT>
std::optional<Problem> firstProblem(const TreeT& tree, const RuleT& rule) {
  auto leaf_check = [&rule](const typename TreeT::LeafNodeType& leaf) -> std::optional<Problem> {
    const auto* values = leaf.buffer().data();
    bool all_ok = true;
    for (openvdb::Index n = 0; n < TreeT::LeafNodeType::SIZE; ++n) all_ok &= rule.ok(values[n]);
    if (all_ok) return std::nullopt;
    for (auto it = leaf.cbeginValueOn(); it; ++it)  // offsets ascend in (x,y,z) order
      if (!rule.ok(*it)) return Problem{it.getCoord(), true, rule.describe(*it), {}};
    return std::nullopt;
  };
  std::optional<Problem> first = firstProblemInLeaves(tree, leaf_check);
  auto tile = tree.cbeginValueOn();
  tile.setMaxDepth(TreeT::ValueOnCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile)
    if (!rule.ok(*tile)) keepFirst(first, Problem{tile.getCoord(), false, rule.describe(*tile), {}});
  return first;
}

[[noreturn]] void fail(const std::string& source, const std::string& grid, const std::string& what) {
  throw MediumError(fmt::format("{}: grid '{}': {}", source, grid, what));
}

[[noreturn]] void fail(const std::string& source, const std::string& grid, const Problem& problem) {
  fail(source, grid,
       fmt::format("{} at {} ({},{},{})", problem.what, problem.voxel ? "voxel" : "tile", problem.where.x(),
                   problem.where.y(), problem.where.z()));
}

// Every active value of `grid` passes `rule`, and its background is finite.
template <typename GridT, typename RuleT>
void checkValues(const GridT& grid, const std::string& source, const RuleT& rule) {
  if (!isFinite(grid.background())) fail(source, grid.getName(), "background is NaN or infinite");
  if (auto problem = firstProblem(grid.tree(), rule)) fail(source, grid.getName(), *problem);
}

template <typename GridT>
void checkFinite(const GridT& grid, const std::string& source) {
  using ValueT = typename GridT::ValueType;
  checkValues(grid, source, valueRule([](const ValueT& v) { return isFinite(v); },
                                      [](const ValueT&) { return std::string("value is NaN or infinite"); }));
}

void checkDensity(const openvdb::FloatGrid& density, const std::string& source, bool whole) {
  if (density.background() != 0.0f)
    fail(source, density.getName(),
         fmt::format("background is {}, expected 0 (inactive voxels are empty space)", density.background()));
  checkValues(density, source, valueRule([](float rho) { return rho >= 0 && rho <= FLT_MAX; },
                                         [](float rho) {
                                           return std::isfinite(rho) ? fmt::format("negative density {}", rho)
                                                                     : std::string("density is NaN or infinite");
                                         }));
  if (whole && openvdb::tools::minMax(density.tree()).max() <= 0) failEmptyDensity(source);
}

bool albedoOk(const openvdb::Vec3s& a) {
  return (a[0] >= 0) & (a[0] <= 1) & (a[1] >= 0) & (a[1] <= 1) & (a[2] >= 0) & (a[2] <= 1);  // false for NaN
}
std::string describeAlbedo(const openvdb::Vec3s& a) {
  return fmt::format("albedo ({}, {}, {}) outside [0,1]", a[0], a[1], a[2]);
}

bool emissionOk(const openvdb::Vec3s& e) {
  return (e[0] >= 0) & (e[0] <= FLT_MAX) & (e[1] >= 0) & (e[1] <= FLT_MAX) & (e[2] >= 0) & (e[2] <= FLT_MAX);  // false for NaN
}
std::string describeEmission(const openvdb::Vec3s& e) {
  if (!isFinite(e)) return fmt::format("emission ({}, {}, {}) is NaN or infinite", e[0], e[1], e[2]);
  return fmt::format("emission ({}, {}, {}) is negative", e[0], e[1], e[2]);
}

// An emission grid (RGB, or grey) emits nothing where it is inactive (docs/medium.md §3b).
template <typename GridT>
void checkEmission(const GridT& emission, const std::string& source) {
  using ValueT = typename GridT::ValueType;
  const openvdb::Vec3s background(emission.background());
  if (background != openvdb::Vec3s(0.0f))
    fail(source, emission.getName(),
         fmt::format("background is ({}, {}, {}), expected 0 (inactive voxels emit nothing)", background[0],
                     background[1], background[2]));
  checkValues(emission, source, valueRule([](const ValueT& e) { return emissionOk(openvdb::Vec3s(e)); },
                                          [](const ValueT& e) { return describeEmission(openvdb::Vec3s(e)); }));
}

// A blackbody_temperature grid (docs/medium.md §3b): kelvin >= 0, background 0, and a Blackbody
// Intensity in [0, 1] if its metadata gives one.
void checkBlackbodyTemperature(const openvdb::FloatGrid& temperature, const std::string& source) {
  if (temperature.background() != 0.0f)
    fail(source, temperature.getName(),
         fmt::format("background is {}, expected 0 (inactive voxels emit nothing)", temperature.background()));
  if (const auto intensity = blackbodyIntensityMetadata(temperature); intensity && !(*intensity >= 0 && *intensity <= 1))
    fail(source, temperature.getName(), fmt::format("metadata {} is {}, expected a number in [0, 1]",
                                                    metadata_names::kBlackbodyIntensity, *intensity));
  checkValues(temperature, source,
              valueRule([](float T) { return T >= 0 && T <= FLT_MAX; },
                        [](float T) { return fmt::format("temperature {} K is {}", T, std::isfinite(T) ? "negative" : "not finite"); }));
}

// Value types the contract requires of a grid name, or nullopt for names it does not define.
std::optional<std::vector<std::string>> requiredValueTypes(const std::string& name) {
  using Types = std::vector<std::string>;
  if (name == grid_names::kDensity || name == grid_names::kHgG || name == grid_names::kPhaseTable ||
      name == grid_names::kBlackbodyTemperature)
    return Types{"float"};
  if (name == grid_names::kAlbedo || name == grid_names::kEmission) return Types{"vec3s", "float"};
  if (name == grid_names::kSggxDiag || name == grid_names::kSggxOffdiag) return Types{"vec3s"};
  if (name == grid_names::kCluster || name == grid_names::kPhaseId || isBlockIndexedGridName(name))
    return Types{"int32"};
  if (isLobeGridName(name)) return Types{name.substr(name.rfind('_')) == "_fraction" ? "float" : "vec3s"};
  return std::nullopt;
}

void checkValueType(const openvdb::GridBase& grid, const std::string& source) {
  const auto required = requiredValueTypes(grid.getName());
  if (!required || std::find(required->begin(), required->end(), grid.valueType()) != required->end()) return;
  fail(source, grid.getName(), fmt::format("holds {} values, expected {}", grid.valueType(), required->front()));
}

// The values the tools use are those of albedo, S and hg_g wherever density > 0, whether or not
// those voxels are active in their own grids (inactive ones read as the stored or background
// value). One pass over the density leaves checks them all.
class WhereDenseCheck {
 public:
  explicit WhereDenseCheck(const Medium& medium) : medium_(medium) {}

  std::optional<Problem> operator()(const openvdb::FloatTree::LeafNodeType& leaf) const {
    const openvdb::Coord origin = leaf.origin();
    using V3 = LeafValues<openvdb::Vec3STree>;
    const V3 albedo = medium_.albedo ? V3(medium_.albedo->tree(), origin) : V3(defaults::kAlbedo);
    const V3 diag = medium_.sggx_diag ? V3(medium_.sggx_diag->tree(), origin) : V3(defaults::kSggxDiag);
    const V3 offdiag = medium_.sggx_offdiag ? V3(medium_.sggx_offdiag->tree(), origin) : V3(defaults::kSggxOffdiag);
    using V1 = LeafValues<openvdb::FloatTree>;
    const V1 hg_g = medium_.hg_g ? V1(medium_.hg_g->tree(), origin) : V1(defaults::kHgG);
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
      if (*it <= 0) continue;
      const openvdb::Index n = it.pos();
      if (auto problem = problemAt(albedo[n], diag[n], offdiag[n], hg_g[n])) {
        return Problem{it.getCoord(), true, fmt::format("{} where density is {}", problem->second, *it),
                       problem->first};
      }
    }
    return std::nullopt;
  }

 private:
  // (grid at fault, what is wrong), if anything.
  static std::optional<std::pair<std::string, std::string>> problemAt(const openvdb::Vec3s& a, const openvdb::Vec3s& d,
                                                                      const openvdb::Vec3s& o, float g) {
    if (!albedoOk(a)) return std::pair{std::string(grid_names::kAlbedo), describeAlbedo(a)};
    if (!isPositiveDefinite(Vec3(d[0], d[1], d[2]), Vec3(o[0], o[1], o[2])))
      return std::pair{std::string(grid_names::kSggxDiag),
                       fmt::format("S (diag {} {} {}, offdiag {} {} {}) is not positive definite", d[0], d[1], d[2],
                                   o[0], o[1], o[2])};
    if (!(g > -1 && g < 1)) return std::pair{std::string(grid_names::kHgG), fmt::format("hg_g {} outside (-1,1)", g)};
    return std::nullopt;
  }

  const Medium& medium_;
};

void checkValuesWhereDense(const Medium& medium, const std::string& source) {
  if (medium.sggx_offdiag && !medium.sggx_diag) fail(source, grid_names::kSggxOffdiag, "present without 'sggx_diag'");
  if (!medium.albedo && !medium.sggx_diag && !medium.hg_g) return;
  const openvdb::FloatTree* density = &medium.density->tree();
  std::unique_ptr<openvdb::FloatTree> voxelized;  // tiles hide per-voxel values: visit every voxel they cover
  if (density->hasActiveTiles()) {
    voxelized = std::make_unique<openvdb::FloatTree>(*density);
    voxelized->voxelizeActiveTiles();
    density = voxelized.get();
  }
  const WhereDenseCheck check(medium);
  if (auto problem = firstProblemInLeaves(*density, check)) fail(source, problem->grid, *problem);
}

void checkMetadata(const Medium& medium, const std::string& source) {
  if (medium.metadata[metadata_names::kSchema]) {  // absent in media from other programs: fine
    auto schema = medium.metadata.getMetadata<openvdb::Int32Metadata>(metadata_names::kSchema);
    if (!schema) throw MediumError(fmt::format("{}: metadata 'schema' is not an int32", source));
    if (schema->value() > metadata_names::kSchemaVersion)
      throw MediumError(fmt::format("{}: medium schema {} is newer than this build reads (schema {})", source,
                                    schema->value(), metadata_names::kSchemaVersion));
  }
  if (medium.metadata[metadata_names::kHgG]) {
    const std::optional<double> g = hgGMetadata(medium.metadata);
    if (!g) throw MediumError(fmt::format("{}: metadata 'hg_g' is not a number", source));
    if (!(*g > -1 && *g < 1)) throw MediumError(fmt::format("{}: metadata 'hg_g' = {} outside (-1,1)", source, *g));
  }
  emissionConvention(medium, source);  // throws unless absent, cycles or pbrt
}

// exemplar_layout, exemplar_stacking: ids in 0..exemplar_count-1, and the metadata that says how big
// a block is.
void checkExemplarLayout(const Medium& medium, const std::string& source) {
  for (const auto& grid : medium.other_grids) {
    if (!isBlockIndexedGridName(grid->getName())) continue;
    const auto count = medium.metadata.getMetadata<openvdb::Int32Metadata>(metadata_names::kExemplarCount);
    const auto block = medium.metadata.getMetadata<openvdb::Vec3IMetadata>(metadata_names::kExemplarBlock);
    if (!count || count->value() < 1 || !block || block->value().x() < 1 || block->value().y() < 1 || block->value().z() < 1)
      fail(source, grid->getName(), "needs metadata 'exemplar_count' (int >= 1) and 'exemplar_block' (vec3i >= 1)");
    const auto& layout = static_cast<const openvdb::Int32Grid&>(*grid);
    for (auto v = layout.cbeginValueOn(); v; ++v)
      if (*v < 0 || *v >= count->value())
        fail(source, grid->getName(),
             fmt::format("exemplar id {} at ({},{},{}) outside 0..{}", *v, v.getCoord().x(), v.getCoord().y(),
                         v.getCoord().z(), count->value() - 1));
  }
}

// Active tiles are voxelised where per-voxel values are needed: refuse a claim beyond the limit
// before that allocates (io/resource_limits.h).
void checkTileVoxels(const openvdb::GridBase& grid, const std::string& source) {
  const openvdb::Index64 tile_voxels = grid.activeVoxelCount() - grid.baseTree().activeLeafVoxelCount();
  const std::uint64_t limit = maxTileVoxels();
  if (tile_voxels > limit)
    fail(source, grid.getName(),
         fmt::format("its active tiles cover {} voxels, more than the limit of {} (VDBAPPEAR_MAX_TILE_VOXELS raises it)",
                     tile_voxels, limit));
}

}  // namespace

void failEmptyDensity(const std::string& source) {
  fail(source, grid_names::kDensity, "empty grid (no voxel with density > 0)");
}

void validateGrid(const openvdb::GridBase& grid, const std::string& source) { validateGridPart(grid, source, true); }

void validateGridPart(const openvdb::GridBase& grid, const std::string& source, bool whole) {
  checkValueType(grid, source);
  checkTileVoxels(grid, source);
  const std::string& name = grid.getName();
  if (name == grid_names::kDensity) {
    checkDensity(static_cast<const openvdb::FloatGrid&>(grid), source, whole);
  } else if (name == grid_names::kAlbedo) {
    if (const auto* rgb = dynamic_cast<const openvdb::Vec3SGrid*>(&grid))
      checkValues(*rgb, source, valueRule(albedoOk, describeAlbedo));
    else
      checkValues(static_cast<const openvdb::FloatGrid&>(grid), source,
                  valueRule([](float a) { return albedoOk(openvdb::Vec3s(a)); },
                            [](float a) { return describeAlbedo(openvdb::Vec3s(a)); }));
  } else if (name == grid_names::kHgG) {
    checkValues(static_cast<const openvdb::FloatGrid&>(grid), source,
                valueRule([](float g) { return g > -1 && g < 1; },
                          [](float g) { return fmt::format("hg_g {} outside (-1,1)", g); }));
  } else if (name == grid_names::kEmission) {
    if (const auto* rgb = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) checkEmission(*rgb, source);
    else checkEmission(static_cast<const openvdb::FloatGrid&>(grid), source);
  } else if (name == grid_names::kBlackbodyTemperature) {
    checkBlackbodyTemperature(static_cast<const openvdb::FloatGrid&>(grid), source);
  } else if (const auto* vec3 = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) {
    checkFinite(*vec3, source);
  } else if (const auto* scalar = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    checkFinite(*scalar, source);
  }
}

void validateAcrossGrids(const Medium& medium, const std::string& source) {
  if (!medium.density) throw MediumError(fmt::format("{}: no grid named '{}'", source, grid_names::kDensity));
  checkMetadata(medium, source);
  if (!medium.transform().isLinear())
    fail(source, grid_names::kDensity,
         fmt::format("its transform ({}) is not linear; media need a linear transform", medium.transform().mapType()));
  for (const auto& grid : medium.grids())
    if (grid->transform() != medium.transform())
      fail(source, grid->getName(), "its transform differs from the density grid's (all grids of a medium share one)");
  checkValuesWhereDense(medium, source);
  checkExemplarLayout(medium, source);
}

void validateMedium(const Medium& medium, const std::string& source) {
  for (const auto& grid : medium.grids()) validateGrid(*grid, source);
  validateAcrossGrids(medium, source);
}

}  // namespace vdbappear
