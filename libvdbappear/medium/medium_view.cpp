#include "libvdbappear/medium/medium_view.h"

#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/phase_tables.h"
#include "libvdbappear/medium/compact_attributes.h"
#include "libvdbappear/medium/emission_light.h"
#include "libvdbappear/medium/majorant_grid.h"
#include "libvdbappear/medium/majorant_traversal.h"
#include "libvdbappear/modularity/instance_mapping.h"
#include "libvdbappear/modularity/instanced_majorant_traversal.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <regex>

namespace vdbappear {

namespace {

Rgb toRgb(const openvdb::Vec3s& v) { return {v[0], v[1], v[2]}; }


}  // namespace

const char* phaseSourceName(PhaseSource source) {
  switch (source) {
    case PhaseSource::kLobes: return "multi-lobe SGGX (lobe grids)";
    case PhaseSource::kSggx: return "SGGX";
    case PhaseSource::kTable: return "tabulated (phase_table)";
    case PhaseSource::kHgGrid: return "Henyey-Greenstein (hg_g grid)";
    case PhaseSource::kHgConstant: return "Henyey-Greenstein (hg_g metadata)";
    case PhaseSource::kIsotropic: return "isotropic";
  }
  return "?";
}

struct LobeGrids {
  openvdb::Vec3SGrid::Ptr diag, offdiag, weight;
};

struct MediumView::Impl {
  MediumPtr medium;
  Interpolation interpolation = Interpolation::kNearest;
  Mat3 world_to_index = Mat3::Identity();  // index = world_to_index * world + index_of_origin
  Vec3 index_of_origin = Vec3::Zero();
  openvdb::FloatGrid::Ptr majorant;
  openvdb::math::BBox<openvdb::Vec3d> majorant_box;  // majorant space
  int majorant_start_level = 0;                        // forEachMajorantSegment's, for rays clipped to the box
  Aabb bounds;
  PhaseSource phase_source = PhaseSource::kIsotropic;
  double hg_constant = 0;
  std::vector<LobeGrids> lobes;
  std::vector<TabulatedPhase> tables;
  openvdb::Int32Grid::Ptr phase_id, cluster;
  int cluster_count = 0;
  std::optional<InstanceMapping> instances;  // an instanced model: lookups go through its layout
  openvdb::Vec3SGrid::Ptr emission;           // docs/medium.md §3b; null: no emission grid
  openvdb::FloatGrid::Ptr blackbody_temperature;  // §3b, kelvin; null: no blackbody light
  PrincipledBlackbody blackbody;
  std::optional<BlackbodyTable> blackbody_colours;  // made only for a medium with blackbody_temperature
  EmissionConvention emission_convention = EmissionConvention::kCycles;
  std::shared_ptr<const CompactAttributes> records;  // a compact medium's albedo and S (medium/compact_attributes.h)
  bool records_sggx = false;                          // S from the records (not ignored)

  bool hasSggx() const { return medium->hasSggx() || records_sggx; }
  bool emits() const { return emission || blackbody_temperature; }
  Rgb blackbodyLight(double kelvin) const {  // Principled Volume's light at this temperature
    return blackbody_temperature ? principledBlackbodyEmission(kelvin, blackbody, *blackbody_colours) : Rgb(Rgb::Zero());
  }

  void findInstances();
  void readEmission();
  void findTransform();
  void findBounds();
  void findPhaseSource();
  void readLobes();
  void readTables();
  void readClusters();
  [[noreturn]] void fail(const std::string& grid, const std::string& what) const {
    throw MediumError(fmt::format("{}: grid '{}': {}", medium->source, grid, what));
  }
};

void MediumView::Impl::findTransform() {
  const openvdb::math::Transform& transform = medium->transform();
  const openvdb::Vec3d b = transform.worldToIndex(openvdb::Vec3d(0, 0, 0));
  index_of_origin = toVec3(b);
  for (int axis = 0; axis < 3; ++axis) {
    openvdb::Vec3d e(0, 0, 0);
    e[axis] = 1;
    world_to_index.col(axis) = toVec3(transform.worldToIndex(e) - b);
  }
}

// An instanced model (docs/modularity.md) renders with nearest lookups: a trilinear stencil on a block
// border reads the neighbouring block, which the per-block majorant does not bound. Its majorant
// stays the block set's, walked through the layout (modularity/instanced_majorant_traversal.h).
void MediumView::Impl::findInstances() {
  instances = InstanceMapping::of(*medium, kMajorantBlock);
  if (!instances) return;
  if (emits())
    fail(emission ? grid_names::kEmission : grid_names::kBlackbodyTemperature,
         "an instanced model cannot emit yet; assemble it without --instanced");
  if (interpolation != Interpolation::kNearest)
    throw MediumError(fmt::format("{}: an instanced model renders with nearest lookups (--interp nearest); for "
                                  "trilinear lookups assemble it without --instanced", medium->source));
}

void MediumView::Impl::readEmission() {
  emission = emissionGrid(*medium);
  blackbody_temperature = blackbodyTemperatureGrid(*medium);
  if (blackbody_temperature) {
    blackbody = blackbodySettings(*blackbody_temperature);
    blackbody_colours.emplace();
  }
  emission_convention = emissionConvention(*medium);
}

void MediumView::Impl::findBounds() {
  const openvdb::CoordBBox box =
      instances ? instances->modelBounds(*medium->density) : framedVoxels(*medium);  // instanced models do not emit
  const openvdb::BBoxd world = worldBoxOfCells(medium->transform(), box);
  bounds.extend(toVec3(world.min()));
  bounds.extend(toVec3(world.max()));
  // An instanced model's majorant voxels (never built): its voxel box in blocks of kMajorantBlock.
  const openvdb::Coord unit(kMajorantBlock);
  const openvdb::CoordBBox m = !instances ? majorant->evalActiveVoxelBoundingBox()
                               : box.empty() ? openvdb::CoordBBox()
                                             : openvdb::CoordBBox(blockOf(box.min(), unit), blockOf(box.max(), unit));
  majorant_box = openvdb::math::BBox<openvdb::Vec3d>(m.min().asVec3d(), m.max().asVec3d() + openvdb::Vec3d(1.0));
  if (!instances) majorant_start_level = majorantWalkStartLevel(majorant->tree(), m);
}

void MediumView::Impl::findPhaseSource() {
  if (findOtherGrid<openvdb::Vec3SGrid>(*medium, "lobe0_weight")) {
    phase_source = PhaseSource::kLobes;
  } else if (hasSggx()) {
    phase_source = PhaseSource::kSggx;
  } else if (findOtherGrid<openvdb::FloatGrid>(*medium, grid_names::kPhaseTable)) {
    phase_source = PhaseSource::kTable;
  } else if (medium->hg_g) {
    phase_source = PhaseSource::kHgGrid;
  } else if (const auto g = hgGMetadata(medium->metadata)) {
    phase_source = PhaseSource::kHgConstant;
    hg_constant = *g;
  }
}

// Lobe j has lobe{j}_weight and lobe{j}_diag (lobe{j}_offdiag optional: zeros). Where a lobe has
// weight and the voxel has density, its S must be positive definite.
void MediumView::Impl::readLobes() {
  auto density = medium->density->getConstAccessor();
  for (int j = 0;; ++j) {
    LobeGrids lobe{findOtherGrid<openvdb::Vec3SGrid>(*medium, fmt::format("lobe{}_diag", j)),
                   findOtherGrid<openvdb::Vec3SGrid>(*medium, fmt::format("lobe{}_offdiag", j)),
                   findOtherGrid<openvdb::Vec3SGrid>(*medium, fmt::format("lobe{}_weight", j))};
    if (!lobe.weight) break;
    if (!lobe.diag) fail(fmt::format("lobe{}_weight", j), fmt::format("present without 'lobe{}_diag'", j));
    if (int(lobes.size()) == ScatteringFunction::kMaxLobes)
      fail(lobe.weight->getName(), fmt::format("more than {} lobes per voxel", ScatteringFunction::kMaxLobes));
    auto diag = lobe.diag->getConstAccessor();
    for (auto w = lobe.weight->cbeginValueOn(); w; ++w) {
      if (!(w->x() > 0 || w->y() > 0 || w->z() > 0)) continue;
      if ((w->x() < 0 || w->y() < 0 || w->z() < 0))
        fail(lobe.weight->getName(), fmt::format("negative lobe weight at ({},{},{})", w.getCoord().x(), w.getCoord().y(), w.getCoord().z()));
      const openvdb::Coord ijk = w.getCoord();
      if (!(density.getValue(ijk) > 0) || !density.isValueOn(ijk)) continue;  // inactive: empty space
      const openvdb::Vec3s off = lobe.offdiag ? lobe.offdiag->tree().getValue(ijk) : openvdb::Vec3s(0.0f);
      if (!isPositiveDefinite(toVec3(diag.getValue(ijk)), toVec3(off)))
        fail(lobe.diag->getName(), fmt::format("S of a lobe with weight is not positive definite at voxel ({},{},{})",
                                               ijk.x(), ijk.y(), ijk.z()));
    }
    lobes.push_back(lobe);
  }
}

// Table t is the row y = t of phase_table, bins along x (docs/medium.md §6).
void MediumView::Impl::readTables() {
  for (std::vector<double>& f : readPhaseTables(*medium)) {
    try {
      tables.emplace_back(std::move(f));
    } catch (const std::exception& e) {
      fail(grid_names::kPhaseTable, fmt::format("table {}: {}", tables.size(), e.what()));
    }
  }
  if (tables.empty()) return;
  phase_id = findOtherGrid<openvdb::Int32Grid>(*medium, grid_names::kPhaseId);
  if (!phase_id) return;
  const int count = int(tables.size());
  if (phase_id->background() < 0 || phase_id->background() >= count)
    fail(grid_names::kPhaseId, fmt::format("background {} outside 0..{}", phase_id->background(), count - 1));
  for (auto id = phase_id->cbeginValueOn(); id; ++id)
    if (*id < 0 || *id >= count)
      fail(grid_names::kPhaseId, fmt::format("table id {} outside 0..{} at ({},{},{})", *id, count - 1,
                                             id.getCoord().x(), id.getCoord().y(), id.getCoord().z()));
}

void MediumView::Impl::readClusters() {
  cluster = findOtherGrid<openvdb::Int32Grid>(*medium, grid_names::kCluster);
  if (!cluster) return;
  for (auto id = cluster->cbeginValueOn(); id; ++id) {
    if (*id < 0) fail(grid_names::kCluster, fmt::format("negative cluster id {}", *id));
    cluster_count = std::max(cluster_count, *id + 1);
  }
}

MediumView::MediumView(const CompactMedium& medium, Interpolation interpolation, bool ignore_sggx)
    : impl_(std::make_unique<Impl>()) {
  impl_->records = medium.attributes;
  impl_->records_sggx = medium.attributes && medium.attributes->hasSggx() && !ignore_sggx;
  build(medium.medium, interpolation, ignore_sggx);
}

MediumView::MediumView(MediumPtr medium, Interpolation interpolation, bool ignore_sggx)
    : impl_(std::make_unique<Impl>()) {
  build(std::move(medium), interpolation, ignore_sggx);
}

void MediumView::build(MediumPtr medium, Interpolation interpolation, bool ignore_sggx) {
  if (ignore_sggx && medium->hasSggx()) {  // lobe grids are ignored below
    medium = std::make_shared<Medium>(*medium);  // shares the grids
    medium->sggx_diag = nullptr;
    medium->sggx_offdiag = nullptr;
  }
  impl_->medium = std::move(medium);
  impl_->interpolation = interpolation;
  impl_->readEmission();
  const bool emits_where_empty = impl_->emits() && impl_->emission_convention == EmissionConvention::kCycles;
  impl_->majorant = buildMajorantGrid(*impl_->medium, interpolation,
                                      emits_where_empty ? voxelEmission(*impl_->medium).get() : nullptr,
                                      impl_->records_sggx ? impl_->records.get() : nullptr);
  impl_->findInstances();
  impl_->findTransform();
  impl_->findBounds();
  impl_->findPhaseSource();
  if (ignore_sggx && impl_->phase_source == PhaseSource::kLobes) impl_->phase_source = PhaseSource::kIsotropic;
  if (impl_->phase_source == PhaseSource::kLobes) impl_->readLobes();
  if (impl_->phase_source == PhaseSource::kTable) impl_->readTables();
  impl_->readClusters();
}

MediumView::~MediumView() = default;

Aabb MediumView::worldBounds() const { return impl_->bounds; }
Interpolation MediumView::interpolation() const { return impl_->interpolation; }
PhaseSource MediumView::phaseSource() const { return impl_->phase_source; }
int MediumView::lobeCount() const { return impl_->phase_source == PhaseSource::kLobes ? int(impl_->lobes.size()) : 1; }
int MediumView::clusterCount() const { return impl_->cluster_count; }
bool MediumView::emits() const { return impl_->emits(); }
std::size_t MediumView::majorantVoxelCount() const {
  return impl_->instances ? impl_->instances->modelMajorantVoxelCount(*impl_->majorant, kMajorantBlock)
                          : impl_->majorant->activeVoxelCount();
}
std::uint64_t MediumView::instancedVoxelCount() const {
  return impl_->instances ? impl_->instances->modelVoxelCount(*impl_->medium->density) : 0;
}
const std::string& MediumView::source() const { return impl_->medium->source; }
bool MediumView::compact() const { return impl_->records != nullptr; }
std::unique_ptr<MediumLookup> MediumView::lookup() const { return std::make_unique<MediumLookup>(*impl_); }

// ---------------------------------------------------------------------------------------------
// Lookups

template <typename GridT>
using OptionalAccessor = std::optional<typename GridT::ConstAccessor>;

template <typename GridT>
OptionalAccessor<GridT> accessorOf(const typename GridT::Ptr& grid) {
  if (!grid) return std::nullopt;
  return grid->getConstAccessor();
}

struct LobeAccessors {
  openvdb::Vec3SGrid::ConstAccessor diag;
  OptionalAccessor<openvdb::Vec3SGrid> offdiag;
  openvdb::Vec3SGrid::ConstAccessor weight;
};

struct MediumLookup::Accessors {
  const InstanceMapping* instances;
  openvdb::FloatGrid::ConstAccessor density, majorant;
  OptionalAccessor<openvdb::Vec3SGrid> albedo, diag, offdiag;
  OptionalAccessor<openvdb::FloatGrid> hg_g;
  OptionalAccessor<openvdb::Int32Grid> phase_id, cluster;
  OptionalAccessor<openvdb::Vec3SGrid> emission;
  OptionalAccessor<openvdb::FloatGrid> temperature;
  std::vector<LobeAccessors> lobes;
  std::optional<CompactAttributes::Accessor> records;  // a compact medium's albedo and S
  bool records_sggx = false;

  explicit Accessors(const MediumView::Impl& view)
      : instances(view.instances ? &*view.instances : nullptr),
        density(view.medium->density->getConstAccessor()),
        majorant(view.majorant->getConstAccessor()),
        albedo(accessorOf<openvdb::Vec3SGrid>(view.medium->albedo)),
        diag(accessorOf<openvdb::Vec3SGrid>(view.medium->sggx_diag)),
        offdiag(accessorOf<openvdb::Vec3SGrid>(view.medium->sggx_offdiag)),
        hg_g(accessorOf<openvdb::FloatGrid>(view.medium->hg_g)),
        phase_id(accessorOf<openvdb::Int32Grid>(view.phase_id)),
        cluster(accessorOf<openvdb::Int32Grid>(view.cluster)),
        emission(accessorOf<openvdb::Vec3SGrid>(view.emission)),
        temperature(accessorOf<openvdb::FloatGrid>(view.blackbody_temperature)) {
    for (const LobeGrids& lobe : view.lobes)
      lobes.push_back({lobe.diag->getConstAccessor(), accessorOf<openvdb::Vec3SGrid>(lobe.offdiag),
                       lobe.weight->getConstAccessor()});
    if (view.records) records.emplace(*view.records);
    records_sggx = view.records_sggx;
  }

  // A compact medium's record of voxel ijk (of the medium's grids), null where the density is inactive.
  const CompactVoxel* record(const openvdb::Coord& ijk) {
    const openvdb::FloatTree::LeafNodeType* leaf = density.probeConstLeaf(ijk);
    if (!leaf) return nullptr;
    const openvdb::Index n = openvdb::FloatTree::LeafNodeType::coordToOffset(ijk);
    return leaf->isValueOn(n) ? &records->at(*leaf, n) : nullptr;
  }

  // The voxel of the medium's grids that model voxel v reads: v itself, or through an instanced
  // model's layout. Every lookup below takes model voxels.
  openvdb::Coord at(const openvdb::Coord& v) const { return instances ? (*instances)(v) : v; }

  Mat3 S(const openvdb::Coord& v) {
    if (records_sggx) {
      const CompactVoxel* r = record(at(v));
      return r ? sggxOf(*r) : Mat3::Identity();
    }
    if (!diag) return Mat3::Identity();
    const openvdb::Coord ijk = at(v);
    const openvdb::Vec3s off = offdiag ? offdiag->getValue(ijk) : openvdb::Vec3s(0.0f);
    return sggxMatrix(toVec3(diag->getValue(ijk)), toVec3(off));
  }
  double wSw(const openvdb::Coord& ijk, const Vec3& w);  // w^T S w
  double rho(const openvdb::Coord& v) {  // inactive voxels are empty space (docs/medium.md §3)
    float value = 0;
    return density.probeValue(at(v), value) ? value : 0.0;
  }
  Rgb albedoAt(const openvdb::Coord& v) {
    if (records) {
      const CompactVoxel* r = record(at(v));
      return r ? albedoOf(*r) : Rgb(Rgb::Ones());  // inactive voxels are empty space: their albedo is not used
    }
    return albedo ? toRgb(albedo->getValue(at(v))) : Rgb::Ones();
  }
  int tableId(const openvdb::Coord& v, int background) {  // checked in readTables
    int id = background;
    return phase_id->probeValue(at(v), id) ? id : background;
  }
  double hgAt(const openvdb::Coord& v) { return hg_g ? hg_g->getValue(at(v)) : 0.0; }
  Rgb emissionAt(const openvdb::Coord& v) {  // inactive voxels emit nothing
    openvdb::Vec3s value(0.0f);
    return emission && emission->probeValue(at(v), value) ? toRgb(value) : Rgb(Rgb::Zero());
  }
  double temperatureAt(const openvdb::Coord& v) {  // kelvin; inactive voxels are at 0 K (the background)
    return temperature ? temperature->getValue(at(v)) : 0.0;
  }
};

namespace {

double wSwOf(const openvdb::Vec3s& d, const openvdb::Vec3s& o, const Vec3& w);

}  // namespace

double MediumLookup::Accessors::wSw(const openvdb::Coord& v, const Vec3& w) {
  if (records_sggx) {
    const CompactVoxel* r = record(at(v));
    return r ? wSwOf(*r, w) : 1.0;
  }
  if (!diag) return 1;
  const openvdb::Coord ijk = at(v);
  return wSwOf(diag->getValue(ijk), offdiag ? offdiag->getValue(ijk) : openvdb::Vec3s(0.0f), w);
}

namespace {

// The 8 voxel centres around an index-space point and their trilinear weights; corner c is
// base + (bit 0, bit 1, bit 2) of c.
struct TrilinearStencil {
  openvdb::Coord base;
  std::array<double, 8> weight;
  explicit TrilinearStencil(const Vec3& p) {
    const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
    base = openvdb::Coord(int(fx), int(fy), int(fz));
    const double x1 = p.x() - fx, y1 = p.y() - fy, z1 = p.z() - fz, x0 = 1 - x1, y0 = 1 - y1, z0 = 1 - z1;
    const double xy[4] = {x0 * y0, x1 * y0, x0 * y1, x1 * y1};
    for (int c = 0; c < 4; ++c) {
      weight[c] = xy[c] * z0;
      weight[c + 4] = xy[c] * z1;
    }
  }
  openvdb::Coord ijk(int c) const { return base.offsetBy(c & 1, (c >> 1) & 1, (c >> 2) & 1); }
};

openvdb::Coord nearestVoxel(const Vec3& p) {
  return openvdb::Coord::round(openvdb::Vec3d(p.x(), p.y(), p.z()));
}

}  // namespace

// The voxel whose discrete data (lobes, phase table id, cluster) a point uses: the nearest one,
// or under trilinear lookups the stencil corner with the largest weight * density, so that a
// collision near an edge, where the nearest voxel may be empty, finds the voxel that made it.
openvdb::Coord discreteVoxel(MediumLookup::Accessors& a, Interpolation interpolation, const Vec3& p) {
  if (interpolation == Interpolation::kNearest) return nearestVoxel(p);
  const TrilinearStencil stencil(p);
  int best = 0;
  double best_weight = -1;
  for (int c = 0; c < 8; ++c) {
    const double w = stencil.weight[c] * a.rho(stencil.ijk(c));
    if (w > best_weight) {
      best_weight = w;
      best = c;
    }
  }
  return stencil.ijk(best);
}

MediumLookup::MediumLookup(const MediumView::Impl& view)
    : view_(view), accessors_(std::make_unique<Accessors>(view)) {}
MediumLookup::~MediumLookup() = default;

namespace {

double wSwOf(const openvdb::Vec3s& d, const openvdb::Vec3s& o, const Vec3& w) {
  return d[0] * w.x() * w.x() + d[1] * w.y() * w.y() + d[2] * w.z() * w.z() +
         2 * (o[0] * w.x() * w.y() + o[1] * w.x() * w.z() + o[2] * w.y() * w.z());
}

// Adds the stencil's active corners in `density` (the leaf at its base): w_c rho_c to rho and
// w_c rho_c max(0, wSw(i)) to rho_wSw, for corner offset i in the leaf. Leaf offsets are x-major
// (64 x + 8 y + z); corner c has dx = bit 0, dy = bit 1, dz = bit 2.
template <typename WSw>
void addStencilCorners(const openvdb::FloatTree::LeafNodeType& density, const TrilinearStencil& stencil, const WSw& wSw,
                       double* rho, double* rho_wSw) {
  const openvdb::Index origin = openvdb::FloatTree::LeafNodeType::coordToOffset(stencil.base);
  for (int c = 0; c < 8; ++c) {
    const openvdb::Index i = origin + ((c & 1) << 6) + ((c & 2) << 2) + ((c & 4) >> 2);
    const double r = density.getValue(i);
    if (!(r > 0) || !density.isValueOn(i)) continue;
    *rho += stencil.weight[c] * r;
    *rho_wSw += stencil.weight[c] * r * std::max(0.0, wSw(i));
  }
}

// The trilinear sums when the whole 2x2x2 stencil lies in one leaf of every grid it needs (7 times
// in 8 along each axis): values come straight from the leaf buffers (or a compact medium's records)
// instead of 8 accessor probes per grid.
bool stencilInOneLeaf(MediumLookup::Accessors& a, const TrilinearStencil& stencil, const Vec3& w, double* rho,
                      double* rho_wSw) {
  if (a.instances) return false;  // the stencil may span two blocks of the layout
  const openvdb::Coord& base = stencil.base;
  if ((base.x() & 7) == 7 || (base.y() & 7) == 7 || (base.z() & 7) == 7) return false;
  const auto* density = a.density.probeConstLeaf(base);
  if (!density) return false;
  if (a.records_sggx) {  // a compact medium: S from the density leaf's records
    const LeafRecords& records = a.records->recordsOf(*density);
    addStencilCorners(*density, stencil, [&](openvdb::Index i) { return wSwOf(records.at(density->getValueMask(), i), w); },
                      rho, rho_wSw);
    return true;
  }
  const openvdb::Vec3STree::LeafNodeType* diag = a.diag ? a.diag->probeConstLeaf(base) : nullptr;
  const openvdb::Vec3STree::LeafNodeType* offdiag = a.offdiag ? a.offdiag->probeConstLeaf(base) : nullptr;
  if ((a.diag && !diag) || (a.offdiag && !offdiag)) return false;
  addStencilCorners(*density, stencil, [&](openvdb::Index i) {
    return diag ? wSwOf(diag->getValue(i), offdiag ? offdiag->getValue(i) : openvdb::Vec3s(0.0f), w) : 1.0;
  }, rho, rho_wSw);
  return true;
}

// sigma_t of voxel ijk toward w: rho sqrt(w^T S w) (Eq. (3), downsampling paper).
double voxelExtinction(MediumLookup::Accessors& a, const openvdb::Coord& ijk, const Vec3& w) {
  const double rho = a.rho(ijk);
  return rho > 0 ? rho * std::sqrt(std::max(0.0, a.wSw(ijk, w))) : 0.0;
}

// sigma_t at an index-space point.
double extinctionAt(MediumLookup::Accessors& a, Interpolation interpolation, const Vec3& p, const Vec3& w) {
  if (interpolation == Interpolation::kNearest) return voxelExtinction(a, nearestVoxel(p), w);
  // Trilinear: rho = sum w_c rho_c, S = sum w_c rho_c S_c / rho (density-weighted), so
  // sigma_t = rho sqrt(w^T S w) = sqrt(rho * sum w_c rho_c w^T S_c w).
  const TrilinearStencil stencil(p);
  double rho = 0, rho_wSw = 0;
  if (stencilInOneLeaf(a, stencil, w, &rho, &rho_wSw)) return std::sqrt(rho * rho_wSw);
  for (int c = 0; c < 8; ++c) {
    const double r = a.rho(stencil.ijk(c));
    if (!(r > 0)) continue;
    rho += stencil.weight[c] * r;
    rho_wSw += stencil.weight[c] * r * std::max(0.0, a.wSw(stencil.ijk(c), w));
  }
  return std::sqrt(rho * rho_wSw);
}

}  // namespace

double MediumLookup::extinction(const Vec3& p, const Vec3& w) {
  return extinctionAt(*accessors_, view_.interpolation, view_.world_to_index * p + view_.index_of_origin, w);
}

void MediumLookup::scattering(const Vec3& world, ScatteringFunction* out) {
  Accessors& a = *accessors_;
  const Vec3 p = view_.world_to_index * world + view_.index_of_origin;
  ScatteringFunction& f = *out;
  f.clear();
  if (view_.phase_source == PhaseSource::kLobes) {  // lobes are discrete: see discreteVoxel
    const openvdb::Coord ijk = a.at(discreteVoxel(a, view_.interpolation, p));  // lobe and cluster grids: read directly
    for (std::size_t slot = 0; slot < a.lobes.size(); ++slot) {
      LobeAccessors& l = a.lobes[slot];
      openvdb::Vec3s w(0.0f);
      if (!l.weight.probeValue(ijk, w)) continue;  // inactive: no such lobe here
      const Rgb weight = toRgb(w);
      if (!(weight > 0).any()) continue;
      const openvdb::Vec3s off = l.offdiag ? l.offdiag->getValue(ijk) : openvdb::Vec3s(0.0f);
      PhaseLobe& added = f.appendLobe(weight, int(slot));  // in place: one ScatteringFunction per collision
      added.kind = PhaseKind::kSggx;
      added.sggx = Sggx(toVec3(l.diag.getValue(ijk)), toVec3(off));
    }
    int id = -1;
    if (a.cluster && a.cluster->probeValue(ijk, id)) f.setCluster(id);
    return;
  }
  // Albedo, S and g: at the nearest voxel, or density-weighted over the trilinear stencil.
  Rgb albedo = Rgb::Zero();
  Mat3 S = Mat3::Zero();
  double g = 0;
  if (view_.interpolation == Interpolation::kNearest) {
    const openvdb::Coord v = nearestVoxel(p);
    albedo = a.albedoAt(v);
    if (view_.phase_source == PhaseSource::kSggx) S = a.S(v);
    if (view_.phase_source == PhaseSource::kHgGrid) g = a.hgAt(v);
  } else {
    const TrilinearStencil stencil(p);
    double total = 0;
    for (int c = 0; c < 8; ++c) {
      const double w = stencil.weight[c] * std::max(0.0, a.rho(stencil.ijk(c)));
      if (!(w > 0)) continue;
      total += w;
      albedo += w * a.albedoAt(stencil.ijk(c));
      if (view_.phase_source == PhaseSource::kSggx) S += w * a.S(stencil.ijk(c));
      if (view_.phase_source == PhaseSource::kHgGrid) g += w * a.hgAt(stencil.ijk(c));
    }
    if (!(total > 0)) return;  // no density here: nothing scatters
    albedo /= total;
    S /= total;
    g /= total;
  }
  PhaseLobe& lobe = f.appendLobe(albedo);
  switch (view_.phase_source) {
    case PhaseSource::kSggx:
      lobe.kind = PhaseKind::kSggx;
      lobe.sggx = Sggx(S);
      break;
    case PhaseSource::kTable:
      lobe.kind = PhaseKind::kTabulated;
      lobe.table = &view_.tables[a.phase_id ? a.tableId(discreteVoxel(a, view_.interpolation, p),
                                                        view_.phase_id->background())
                                            : 0];
      break;
    case PhaseSource::kHgGrid:
    case PhaseSource::kHgConstant:
      lobe.kind = PhaseKind::kHenyeyGreenstein;
      lobe.g = view_.phase_source == PhaseSource::kHgGrid ? g : view_.hg_constant;
      break;
    default: break;  // isotropic
  }
}

int MediumLookup::cluster(const Vec3& world) {
  if (!accessors_->cluster) return -1;
  const openvdb::Coord v =
      discreteVoxel(*accessors_, view_.interpolation, view_.world_to_index * world + view_.index_of_origin);
  int id = 0;
  return accessors_->cluster->probeValue(accessors_->at(v), id) ? id : -1;
}

namespace {

// The ray in majorant space (m = (index + 1/2) / B), clipped to the majorant grid's box, with t
// the world distance along the unit direction d.
bool majorantRay(const MediumView::Impl& view, const Vec3& o, const Vec3& d, double t_max, MajorantRay* ray) {
  const Vec3 o_m = (view.world_to_index * o + view.index_of_origin + Vec3::Constant(0.5)) / kMajorantBlock;
  const Vec3 d_m = view.world_to_index * d / kMajorantBlock;
  *ray = MajorantRay(openvdb::Vec3d(o_m.x(), o_m.y(), o_m.z()), openvdb::Vec3d(d_m.x(), d_m.y(), d_m.z()), 0.0, t_max);
  return !view.majorant_box.empty() && ray->clip(view.majorant_box) && ray->t1() > ray->t0();
}

// fn(t0, t1, sigma_maj) along the ray's non-empty majorant segments: the majorant grid's, or an
// instanced model's walked through its layout.
template <typename Fn>
bool forEachSegment(const MediumView::Impl& view, MediumLookup::Accessors& accessors, const MajorantRay& ray, Fn&& fn) {
  if (view.instances)
    return forEachInstancedMajorantSegment(ray, *view.instances, kMajorantBlock, accessors.majorant, std::forward<Fn>(fn));
  return forEachMajorantSegment(ray, accessors.majorant, std::forward<Fn>(fn), view.majorant_start_level);
}

}  // namespace

namespace {

// Samples majorant events (tentative collisions) along the ray, exponentially distributed in the
// majorant optical depth, and calls on_event(t, sigma_t(t), sigma_maj) for each, in order, until
// it returns false or the ray ends (pbrt-v4's SampleT_maj).
template <typename OnEvent>
void forEachMajorantEvent(const MediumView::Impl& view, MediumLookup::Accessors& accessors, TrackingStats& stats,
                          const Vec3& o, const Vec3& d, double t_max, RandomStream& rng, OnEvent&& on_event) {
  MajorantRay ray;
  if (!majorantRay(view, o, d, t_max, &ray)) return;
  const Vec3 o_index = view.world_to_index * o + view.index_of_origin;
  const Vec3 d_index = view.world_to_index * d;
  double tau = -std::log(1 - rng.uniform());  // optical depth to the next event
  // Nearest-voxel media are constant within a voxel and the direction is the walk's, so events that
  // fall in the voxel of the previous one share its sigma_t: one lookup per voxel, not per event.
  const bool nearest = view.interpolation == Interpolation::kNearest;
  openvdb::Coord last_voxel;
  double last_sigma_t = -1;
  const auto extinction = [&](const Vec3& p) {
    if (!nearest) return extinctionAt(accessors, view.interpolation, p, d);
    const openvdb::Coord voxel = nearestVoxel(p);
    if (last_sigma_t < 0 || voxel != last_voxel) {
      last_voxel = voxel;
      last_sigma_t = voxelExtinction(accessors, voxel, d);
    }
    return last_sigma_t;
  };
  forEachSegment(view, accessors, ray, [&](double t0, double t1, double sigma_maj) {
    for (double t = t0;;) {
      const double dt = tau / sigma_maj;
      if (t + dt >= t1) {
        tau -= sigma_maj * (t1 - t);
        return true;
      }
      t += dt;
      ++stats.tentative_collisions;
      const double sigma_t = extinction(o_index + t * d_index);
      if (sigma_t > sigma_maj) ++stats.majorant_violations;
      if (!on_event(t, sigma_t, sigma_maj)) return false;
      tau = -std::log(1 - rng.uniform());
    }
  });
}

}  // namespace

namespace {

// The light emitted per unit length at index-space point p (docs/medium.md §3b), given sigma_t
// there toward the ray's direction: E under the cycles convention; sigma_a Le = sigma_t (1 - albedo)
// Le under pbrt's, with (1 - albedo) Le weighted by density over the trilinear stencil. The
// blackbody light is that of the interpolated temperature, as Cycles interpolates the attribute
// before its Principled Volume makes light of it.
Rgb emittedAt(MediumLookup::Accessors& a, const MediumView::Impl& view, const Vec3& p, double sigma_t) {
  const bool per_length = view.emission_convention == EmissionConvention::kCycles;
  if (!per_length && !(sigma_t > 0)) return Rgb::Zero();
  if (view.interpolation == Interpolation::kNearest) {
    const openvdb::Coord v = nearestVoxel(p);
    const Rgb light = a.emissionAt(v) + view.blackbodyLight(a.temperatureAt(v));
    return per_length ? light : Rgb(sigma_t * (1 - a.albedoAt(v)) * light);
  }
  const TrilinearStencil stencil(p);
  Rgb sum = Rgb::Zero(), absorbing = Rgb::Zero();  // pbrt: sums of w rho (1 - a) Le and of w rho (1 - a)
  double kelvin = 0, rho_sum = 0;
  for (int c = 0; c < 8; ++c) {
    kelvin += stencil.weight[c] * a.temperatureAt(stencil.ijk(c));
    if (per_length) {
      sum += stencil.weight[c] * a.emissionAt(stencil.ijk(c));
      continue;
    }
    const double w = stencil.weight[c] * a.rho(stencil.ijk(c));
    if (!(w > 0)) continue;
    rho_sum += w;
    absorbing += w * (1 - a.albedoAt(stencil.ijk(c)));
    sum += w * (1 - a.albedoAt(stencil.ijk(c))) * a.emissionAt(stencil.ijk(c));
  }
  const Rgb blackbody = view.blackbodyLight(kelvin);
  if (per_length) return sum + blackbody;
  return rho_sum > 0 ? Rgb(sigma_t * (sum + absorbing * blackbody) / rho_sum) : Rgb(Rgb::Zero());
}

}  // namespace

std::optional<double> MediumLookup::sampleCollision(const Vec3& o, const Vec3& d, double t_max, RandomStream& rng,
                                                    Rgb* emitted) {
  std::optional<double> collision;
  const bool score_emission = emitted && view_.emits();
  const Vec3 o_index = view_.world_to_index * o + view_.index_of_origin, d_index = view_.world_to_index * d;
  forEachMajorantEvent(view_, *accessors_, stats_, o, d, t_max, rng, [&](double t, double sigma_t, double sigma_maj) {
    // Every majorant event, real or null, scores E / sigma_maj: the events' density is sigma_maj T,
    // so the sum estimates the integral of T E along the ray up to the collision (pbrt-v4 likewise).
    if (score_emission) *emitted += emittedAt(*accessors_, view_, o_index + t * d_index, sigma_t) / sigma_maj;
    if (rng.uniform() * sigma_maj >= sigma_t) return true;  // a null collision
    collision = t;
    return false;
  });
  return collision;
}

double MediumLookup::transmittance(const Vec3& o, const Vec3& d, double t_max, RandomStream& rng) {
  // Below this weight the walk goes on with probability T / kRouletteBelow at weight kRouletteBelow:
  // unbiased, and it stops most walks deep in a dense medium early. Chosen on the twill and cloud
  // benchmarks (scripts/bench_render.py): 0.3 needs 12% less time to equal noise than halving
  // below 0.1 did; 0.02, 0.1, 0.3, 0.5, 0.6 and 0.9 were measured.
  constexpr double kRouletteBelow = 0.3;
  double T = 1;
  forEachMajorantEvent(view_, *accessors_, stats_, o, d, t_max, rng, [&](double, double sigma_t, double sigma_maj) {
    T *= 1 - sigma_t / sigma_maj;
    if (T < kRouletteBelow) {  // Russian roulette keeps the estimate unbiased
      if (rng.uniform() * kRouletteBelow >= T) {
        T = 0;
        return false;
      }
      T = kRouletteBelow;
    }
    return true;
  });
  return std::max(T, 0.0);
}

double MediumLookup::majorantOpticalDepth(const Vec3& o, const Vec3& d, double t_max) {
  MajorantRay ray;
  if (!majorantRay(view_, o, d, t_max, &ray)) return 0;
  double depth = 0;
  forEachSegment(view_, *accessors_, ray, [&](double t0, double t1, double sigma_maj) {
    depth += sigma_maj * (t1 - t0);
    return true;
  });
  return depth;
}

}  // namespace vdbappear
