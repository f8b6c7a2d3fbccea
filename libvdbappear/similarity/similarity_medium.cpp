#include "libvdbappear/similarity/similarity_medium.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/phase_tables.h"
#include "libvdbappear/similarity/altered_coefficients.h"
#include "libvdbappear/similarity/g_quantiser.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace vdbappear {
namespace {

using DensityLeaves = openvdb::tree::LeafManager<openvdb::FloatTree>;

void checkOneDimensionalPhase(const Medium& medium) {
  const char* why = "the similarity relations need a 1-D phase function (hg_g or phase_table); an SGGX phase "
                    "function depends on the incident direction";
  if (medium.hasSggx())
    throw MediumError(fmt::format("{}: grid '{}': {}", medium.source,
                                  medium.sggx_diag ? grid_names::kSggxDiag : grid_names::kSggxOffdiag, why));
  for (const auto& grid : medium.other_grids)
    if (isLobeGridName(grid->getName())) throw MediumError(fmt::format("{}: grid '{}': {}", medium.source, grid->getName(), why));
}

// One thread's lookups into the input grids (OpenVDB accessors are not thread-safe).
struct VoxelInputs {
  std::optional<openvdb::Vec3SGrid::ConstAccessor> albedo;
  std::optional<openvdb::FloatGrid::ConstAccessor> g;
  std::optional<openvdb::Int32Grid::ConstAccessor> ids;

  explicit VoxelInputs(const Medium& medium) {
    if (medium.albedo) albedo.emplace(medium.albedo->getConstAccessor());
    if (medium.hg_g) g.emplace(medium.hg_g->getConstAccessor());
    if (auto grid = findOtherGrid<openvdb::Int32Grid>(medium, grid_names::kPhaseId)) ids.emplace(grid->getConstAccessor());
  }
  Rgb albedoAt(const openvdb::Coord& ijk) { return albedo ? Rgb(toVec3(albedo->getValue(ijk)).array()) : Rgb(1, 1, 1); }
};

// fn(leaf, offset, ijk, density, inputs) for every active voxel with density > 0, leaves in parallel.
template <typename Fn>
void forEachOccupiedVoxel(DensityLeaves& leaves, const Medium& input, const Fn& fn) {
  tbb::parallel_for(leaves.leafRange(), [&](const DensityLeaves::LeafRange& range) {
    VoxelInputs inputs(input);
    for (auto leaf = range.begin(); leaf; ++leaf)
      for (auto v = leaf->beginValueOn(); v; ++v)
        if (*v > 0) fn(*leaf, v.pos(), v.getCoord(), double(*v), inputs);
  });
}

// The distinct phase functions of a medium (the future tables) and which one each voxel has.
class PhaseSet {
 public:
  PhaseSet(const Medium& medium, DensityLeaves& leaves, const MediumSimilarityOptions& options, MediumSimilarityResult& result);

  std::vector<PhaseMoments> phases;  // by table id
  std::vector<std::string> sources;
  std::vector<std::uint64_t> voxels;
  bool quantised() const { return bool(quantiser_); }

  int tableOf(const openvdb::Coord& ijk, VoxelInputs& inputs) const {
    if (quantiser_) return table_of_level_[quantiser_->level(inputs.g->getValue(ijk))];
    return inputs.ids && from_tables_ ? inputs.ids->getValue(ijk) : 0;
  }

 private:
  void findLevels(const Medium& medium, DensityLeaves& leaves, int max_order, MediumSimilarityResult& result);
  void countVoxels(const Medium& medium, DensityLeaves& leaves);

  bool from_tables_ = false;
  std::optional<GQuantiser> quantiser_;
  std::vector<int> table_of_level_;
};

PhaseSet::PhaseSet(const Medium& medium, DensityLeaves& leaves, const MediumSimilarityOptions& options,
                   MediumSimilarityResult& result) {
  const int max_order = options.phase.max_order;
  const std::vector<std::vector<double>> tables = readPhaseTables(medium);
  if (!tables.empty()) {
    from_tables_ = true;
    for (std::size_t t = 0; t < tables.size(); ++t) {
      try {
        phases.push_back(tablePhaseMoments(tables[t], max_order));
      } catch (const std::exception& e) {
        throw MediumError(fmt::format("{}: grid '{}': table {}: {}", medium.source, grid_names::kPhaseTable, t, e.what()));
      }
      sources.push_back(fmt::format("phase_table {}", t));
    }
  } else if (medium.hg_g) {
    if (!(options.moment_tolerance > 0)) throw std::invalid_argument("the moment tolerance must be positive");
    quantiser_.emplace(options.moment_tolerance, max_order);
    findLevels(medium, leaves, max_order, result);
  } else {
    const double g = hgGMetadata(medium.metadata).value_or(0.0);
    phases.push_back(henyeyGreensteinPhaseMoments(g, max_order));
    sources.push_back(fmt::format("hg g={:g}", g));
  }
  countVoxels(medium, leaves);
}

// The quantisation levels in use (ascending g: table ids) and the largest moment error made.
void PhaseSet::findLevels(const Medium& medium, DensityLeaves& leaves, int max_order, MediumSimilarityResult& result) {
  const GQuantiser& q = *quantiser_;
  tbb::combinable<std::vector<char>> used([&] { return std::vector<char>(q.levels(), 0); });
  tbb::combinable<double> max_error([] { return 0.0; });
  forEachOccupiedVoxel(leaves, medium, [&](auto&, auto, const openvdb::Coord& ijk, double, VoxelInputs& inputs) {
    const double g = inputs.g->getValue(ijk);
    const int level = q.level(g);
    used.local()[level] = 1;
    double error = 0, power = 1, power_q = 1;
    for (int n = 1; n <= max_order; ++n) {
      power *= g;
      power_q *= q.value(level);
      error = std::max(error, std::abs(power - power_q));
    }
    max_error.local() = std::max(max_error.local(), error);
  });
  std::vector<char> all(q.levels(), 0);
  used.combine_each([&](const std::vector<char>& u) { for (int l = 0; l < q.levels(); ++l) all[l] |= u[l]; });
  table_of_level_.assign(q.levels(), -1);
  for (int l = 0; l < q.levels(); ++l) {
    if (!all[l]) continue;
    table_of_level_[l] = int(phases.size());
    phases.push_back(henyeyGreensteinPhaseMoments(q.value(l), max_order));
    sources.push_back(fmt::format("hg g={:.6g}", q.value(l)));
  }
  result.g_levels = q.levels();
  result.moment_tolerance = (max_order * q.step()) / 2;
  result.max_moment_error = max_error.combine([](double a, double b) { return std::max(a, b); });
}

// Voxels per table; a phase_id outside the tables is refused (smallest coordinate reported).
void PhaseSet::countVoxels(const Medium& medium, DensityLeaves& leaves) {
  const int count = int(phases.size());
  tbb::combinable<std::vector<std::uint64_t>> counts([&] { return std::vector<std::uint64_t>(count, 0); });
  tbb::combinable<std::optional<std::pair<openvdb::Coord, int>>> bad;
  forEachOccupiedVoxel(leaves, medium, [&](auto&, auto, const openvdb::Coord& ijk, double, VoxelInputs& inputs) {
    const int t = tableOf(ijk, inputs);
    if (t >= 0 && t < count) {
      ++counts.local()[t];
    } else {
      auto& b = bad.local();
      if (!b || ijk < b->first) b = std::make_pair(ijk, t);
    }
  });
  std::optional<std::pair<openvdb::Coord, int>> first;
  bad.combine_each([&](const auto& b) { if (b && (!first || b->first < first->first)) first = b; });
  if (first)
    throw MediumError(fmt::format("{}: grid '{}': table id {} outside 0..{} at voxel ({},{},{})", medium.source,
                                  grid_names::kPhaseId, first->second, count - 1, first->first.x(), first->first.y(),
                                  first->first.z()));
  voxels.assign(count, 0);
  counts.combine_each([&](const std::vector<std::uint64_t>& c) { for (int t = 0; t < count; ++t) voxels[t] += c[t]; });
}

// Algorithm 1 for every distinct phase function: in runs of kWarmRun consecutive tables (ascending
// g when quantised), the runs in parallel; within a run each table's QPs start from the previous
// table's (QpWarmStarts). The runs do not depend on the thread count, and the tables would be the
// same without them.
constexpr std::size_t kWarmRun = 64;

std::vector<AlteredTable> alterPhases(const PhaseSet& set, const Medium& medium, const SimilarityOptions& options,
                                      ProgressBar* progress) {
  std::vector<AlteredTable> tables(set.phases.size());
  const std::size_t runs = (tables.size() + kWarmRun - 1) / kWarmRun;
  tbb::parallel_for(std::size_t(0), runs, [&](std::size_t run) {
    QpWarmStarts warm;
    for (std::size_t t = run * kWarmRun; t < std::min(tables.size(), (run + 1) * kWarmRun); ++t) {
      try {
        tables[t] = {set.sources[t], set.phases[t].moments.at(1), computeAlteredPhase(set.phases[t], options, &warm),
                     set.voxels[t]};
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("{}: phase function {}: {}", medium.source, set.sources[t], e.what()));
      }
      if (progress) progress->advance();
    }
  });
  return tables;
}

// A grid of type GridT with the (voxelised) topology of `density`, every leaf present.
template <typename GridT>
typename GridT::Ptr gridOnDensityTopology(typename GridT::Ptr grid, const openvdb::FloatGrid& density) {
  grid->tree().topologyUnion(density.tree());
  grid->tree().voxelizeActiveTiles();
  return grid;
}

void writeAlteredVoxels(const Medium& input, DensityLeaves& leaves, const PhaseSet& set,
                        const std::vector<AlteredTable>& tables, openvdb::Vec3SGrid* albedo, openvdb::Int32Grid* ids,
                        MediumSimilarityResult& result) {
  tbb::combinable<double> max_error([] { return 0.0; });
  forEachOccupiedVoxel(leaves, input, [&](openvdb::FloatTree::LeafNodeType& leaf, openvdb::Index offset,
                                          const openvdb::Coord& ijk, double density, VoxelInputs& inputs) {
    const int t = set.tableOf(ijk, inputs);
    const AlteredCoefficients altered = alterCoefficients(density, inputs.albedoAt(ijk), tables[t].phase.alpha, tables[t].f1);
    leaf.setValueOnly(offset, float(altered.density));
    if (albedo) albedo->tree().probeLeaf(ijk)->setValueOnly(offset, toVec3s(Vec3(altered.albedo.matrix())));
    if (ids) ids->tree().probeLeaf(ijk)->setValueOn(offset, t);
    max_error.local() = std::max(max_error.local(), altered.reduced_attenuation_error);
  });
  result.max_reduced_attenuation_error = max_error.combine([](double a, double b) { return std::max(a, b); });
}

void removeGrid(Medium& medium, const std::string& name) {
  auto& grids = medium.other_grids;
  grids.erase(std::remove_if(grids.begin(), grids.end(), [&](const auto& g) { return g->getName() == name; }), grids.end());
}

}  // namespace

MediumSimilarityResult alterMedium(const Medium& input, const MediumSimilarityOptions& options, ProgressBar* progress) {
  checkOneDimensionalPhase(input);
  MediumSimilarityResult result;
  auto out = std::make_shared<Medium>(input);  // shares the grids it does not replace
  out->density = input.density->deepCopy();
  out->density->tree().voxelizeActiveTiles();
  DensityLeaves leaves(out->density->tree());

  const PhaseSet set(input, leaves, options, result);
  for (std::uint64_t v : set.voxels) result.voxels += v;
  if (progress) progress->setTotal(set.phases.size());
  result.tables = alterPhases(set, input, options.phase, progress);
  if (progress) progress->finish();

  if (input.albedo) out->albedo = gridOnDensityTopology<openvdb::Vec3SGrid>(input.albedo->deepCopy(), *out->density);
  openvdb::Int32Grid::Ptr ids;
  if (set.quantised()) {
    ids = gridOnDensityTopology<openvdb::Int32Grid>(openvdb::Int32Grid::create(0), *out->density);
    ids->setName(grid_names::kPhaseId);
    ids->setTransform(out->density->transform().copy());
  }
  writeAlteredVoxels(input, leaves, set, result.tables, out->albedo.get(), ids.get(), result);

  std::vector<std::vector<double>> tables;
  for (const AlteredTable& t : result.tables) tables.push_back(t.phase.table);
  setPhaseTables(*out, tables);
  if (ids) {
    removeGrid(*out, grid_names::kPhaseId);
    out->other_grids.push_back(ids);
  }
  // The original asymmetry no longer describes the altered medium: drop it, and say so.
  if (input.hg_g) result.notes.push_back("removed grid 'hg_g': its phase functions are now the altered tables in 'phase_table'");
  if (hgGMetadata(input.metadata)) result.notes.push_back("removed metadata 'hg_g': its phase function is now the altered table in 'phase_table'");
  out->hg_g = nullptr;
  out->metadata.removeMeta(metadata_names::kHgG);
  result.medium = out;
  return result;
}

}  // namespace vdbappear
