#include "libvdbappear/io/medium_slabs.h"

#include "libvdbappear/io/grid_presets.h"
#include "libvdbappear/io/mapped_grids.h"
#include "libvdbappear/io/mapped_vdb_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_of_grids.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/io/slab_tree_index.h"
#include "libvdbappear/io/vdb_read_error.h"
#include "libvdbappear/math/block_index.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <openvdb/tools/Count.h>
#include <openvdb/util/logging.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

namespace vdbappear {

namespace {

// The internal nodes of a tree (5-4-3): a slab's leaves bring theirs along.
template <typename TreeT>
constexpr std::uint64_t kNode2Bytes = sizeof(typename TreeT::RootNodeType::ChildNodeType);
template <typename TreeT>
constexpr std::uint64_t kNode1Bytes = sizeof(typename TreeT::RootNodeType::ChildNodeType::ChildNodeType);

template <typename GridT>
std::uint64_t leafBytesOf(const GridT&) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  return sizeof(LeafT) + LeafT::SIZE * sizeof(typename GridT::ValueType);
}

bool slabType(const openvdb::GridBase& grid) {
  return grid.apply<SlabGridTypes>([](const auto&) {});
}

// The bytes of each band's leaves, of the internal nodes they bring along and of its output leaves,
// and what stays in memory throughout (each leaf's node on the input file's side, and on the output's
// scratch files' side: io/spilled_medium.h), for one grid, and for `extra_outputs` output grids of
// Vec3s values (the most a contract grid takes) with its output's topology.
template <typename GridT>
void addGridBytes(const GridT& grid, const SlabTreeIndex& index, int band, int extra_outputs,
                  std::map<int, std::uint64_t>& band_bytes, std::uint64_t& resident_bytes) {
  using TreeT = typename GridT::TreeType;
  // An output leaf whose values wait on disk: its node, masks and file reference, with the
  // allocator's share (measured: 266 and 284 bytes a leaf for the 1024^3 twill's density and albedo
  // read with OpenVDB's delayed loading).
  constexpr std::uint64_t kOnFileLeafBytes = 288;
  const std::uint64_t bytes = leafBytesOf(grid);
  const std::uint64_t output_bytes = bytes + std::uint64_t(extra_outputs) * leafBytesOf(openvdb::Vec3SGrid());
  std::set<openvdb::Coord> blocks;                       // the output's leaves
  std::set<std::tuple<int, int, openvdb::Coord>> nodes;  // (band, level, internal node) a band's leaves need
  index.forEachLeaf([&](const openvdb::Coord& origin) {
    const int b = floorDiv(origin.x(), band);
    for (const int log2 : {7, 12})  // the two internal levels: 128^3 and 4096^3 voxels
      if (nodes.insert({b, log2, blockOf(origin, openvdb::Coord(1 << log2))}).second)
        band_bytes[b] += log2 == 7 ? kNode1Bytes<TreeT> : kNode2Bytes<TreeT>;
    band_bytes[b] += bytes;
    if (blocks.insert(blockOf(origin, openvdb::Coord(band))).second) band_bytes[b] += output_bytes;  // its output leaves
  });
  resident_bytes += index.memoryBytes();
  if (const auto* tiles = static_cast<const GridT*>(index.tiles().get())) {
    auto tile = tiles->tree().cbeginValueAll();
    tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {  // a tile's part in a band, as leaves
      if (!tile.isValueOn() && *tile == grid.background()) continue;
      const openvdb::CoordBBox box = tile.getBoundingBox();
      const std::uint64_t leaves_per_band =
          (std::uint64_t(box.dim().y()) * std::uint64_t(box.dim().z()) / 64 + 1) * std::uint64_t(band / 8 + 1);
      for (int b = floorDiv(box.min().x(), band); b <= floorDiv(box.max().x(), band); ++b) band_bytes[b] += leaves_per_band * bytes;
      for (auto c = blocksOf(box, openvdb::Coord(band)).begin(); c; ++c)
        if (blocks.insert(*c).second) band_bytes[(*c).x()] += output_bytes;  // blocks are bands along x
    }
  }
  resident_bytes += blocks.size() * kOnFileLeafBytes * (1 + extra_outputs);  // the output's leaves, their values on disk
}

// Consecutive bands packed into slabs of at most `slab_bytes` (a band alone may exceed it).
std::vector<SlabRange> packSlabs(const std::map<int, std::uint64_t>& band_bytes, int band, std::uint64_t slab_bytes) {
  std::vector<SlabRange> slabs;
  std::uint64_t used = 0;
  for (const auto& [index, bytes] : band_bytes) {
    const int x0 = index * band, x1 = x0 + band;
    if (!slabs.empty() && slabs.back().second == x0 && used + bytes <= slab_bytes) {
      slabs.back().second = x1;
      used += bytes;
    } else {
      slabs.push_back({x0, x1});
      used = bytes;
    }
  }
  return slabs;
}

// A voxel-indexed grid's stand-in where only its name, type and whether it holds a voxel matter
// (the grid mapping's checks and notes): its header, with one active voxel if the grid has any.
openvdb::GridBase::Ptr standIn(const openvdb::GridBase& header, const SlabTreeIndex& index) {
  openvdb::GridBase::Ptr grid = header.copyGridWithNewTree();
  if (index.activeVoxelCount() > 0)
    grid->apply<SlabGridTypes>([](auto& typed) { typed.tree().setValueOn(openvdb::Coord(0), typed.background()); });
  return grid;
}

// x rounded up to three significant digits: a budget that is enough.
double roundedUp(double x) {
  const double step = std::pow(10.0, std::floor(std::log10(x)) - 2);
  return std::ceil(x / step) * step;
}

}  // namespace

MediumSlabs::MediumSlabs(const std::string& path, const GridMapping& mapping) : path_(path) {
  openvdb::initialize();
  // A damaged file fails with a MediumError below; OpenVDB's own log of it (log4cplus, not
  // configured here) would add a line that says only that no logger is configured.
  openvdb::logging::setLevel(openvdb::logging::Level::Fatal);
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw MediumError(fmt::format("{}: no such file", path));
  if (std::filesystem::is_directory(path, error)) throw MediumError(fmt::format("{}: is a directory", path));
  file_ = std::make_unique<MappedVdbFile>(path);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < file_->gridCount(); ++i) names.push_back(file_->descriptor(i).gridName());
  checkGridNames(names, path);
  metadata_ = std::make_shared<openvdb::MetaMap>(file_->metadata());
  why_not_ = file_->whyNotInParts();
  for (std::size_t i = 0; i < file_->gridCount() && !why_not_; ++i)
    if (!slabType(*file_->header(i)))
      why_not_ = fmt::format("grid '{}' holds {} values", names[i], file_->header(i)->valueType());
  if (why_not_) return;
  indices_.resize(file_->gridCount());
  for (std::size_t i = 0; i < file_->gridCount(); ++i) {
    try {
      if (isVoxelIndexed(names[i])) {
        indices_[i] = std::make_unique<SlabTreeIndex>(*file_, i);
        grids_.push_back(file_->header(i)->copyGridWithNewTree());
      } else {
        grids_.push_back(SlabTreeIndex(*file_, i).readWhole());
      }
    } catch (const std::exception& e) {
      throw MediumError(fmt::format("{}: grid '{}': cannot be read ({})", path, names[i], vdbReadError(e)));
    }
    file_->releasePages();
  }
  // A mapping makes grids from whole source grids: such a file is read whole (readMedium).
  openvdb::GridPtrVec stand_ins;
  for (std::size_t i = 0; i < grids_.size(); ++i) stand_ins.push_back(indices_[i] ? standIn(*grids_[i], *indices_[i]) : grids_[i]);
  if (!mapping.rules.empty()) {
    why_not_ = "--grid rules apply to it";
  } else if (!presetRules(stand_ins, mapping.preset, {}).empty()) {
    why_not_ = "a preset maps its grids (--from none reads them as they are)";
  } else {
    notes_ = applyGridMapping(stand_ins, mapping, path).notes;  // names, and whether a grid holds voxels
  }
}

MediumSlabs::~MediumSlabs() = default;

MediumSlabs::Plan MediumSlabs::plan(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes,
                                    int extra_output_grids) const {
  std::map<int, std::uint64_t> band_bytes;  // band index -> bytes of its leaves, every voxel grid
  Plan plan;
  for (std::size_t i = 0; i < grids_.size(); ++i)
    if (indices_[i])
      grids_[i]->apply<SlabGridTypes>(
          [&](const auto& grid) {
            const int extra = grid.getName() == grid_names::kDensity ? extra_output_grids : 0;
            addGridBytes(grid, *indices_[i], band, extra, band_bytes, plan.resident_bytes);
          });
  for (const auto& entry : band_bytes) plan.largest_band_bytes = std::max(plan.largest_band_bytes, entry.second);
  const std::uint64_t free_bytes = memory_bytes > plan.resident_bytes ? memory_bytes - plan.resident_bytes : 0;
  if (plan.largest_band_bytes > free_bytes) return plan;  // no slabs: one band does not fit
  plan.slabs = packSlabs(band_bytes, band, std::min(free_bytes, std::max(slab_target_bytes, plan.largest_band_bytes)));
  return plan;
}

MediumSlabs::Plan MediumSlabs::planWithin(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes,
                                          int extra_output_grids) const {
  Plan fitted = plan(band, memory_bytes, slab_target_bytes, extra_output_grids);
  if (fitted.slabs.empty() && fitted.largest_band_bytes > 0) {
    const double needed = double(fitted.resident_bytes + fitted.largest_band_bytes) / 1e9;
    throw MediumError(fmt::format("{}: a memory budget of {:.3g} GB is too small: one slab of {} voxels along x needs "
                                  "{:.3g} GB with what stays in memory (--memory {:.3g} or more)",
                                  path_, double(memory_bytes) / 1e9, band, needed, roundedUp(needed)));
  }
  return fitted;
}

MediumPtr MediumSlabs::slab(const SlabRange& range) {
  file_->releasePages();
  const openvdb::CoordBBox box(openvdb::Coord(range.first, openvdb::Coord::min().y(), openvdb::Coord::min().z()),
                               openvdb::Coord(range.second - 1, openvdb::Coord::max().y(), openvdb::Coord::max().z()));
  openvdb::GridPtrVec grids;
  for (std::size_t i = 0; i < grids_.size(); ++i) {
    if (!indices_[i]) {
      grids.push_back(grids_[i]->deepCopyGrid());
      continue;
    }
    openvdb::GridBase::Ptr part;
    try {
      part = indices_[i]->readLeaves(box);
    } catch (const std::exception& e) {
      throw MediumError(fmt::format("{}: grid '{}': cannot be read ({})", path_, grids_[i]->getName(), vdbReadError(e)));
    }
    indices_[i]->addTiles(*part, box);
    grids.push_back(part);
  }
  for (const auto& grid : grids) validateGridPart(*grid, path_, /*whole=*/false);
  for (const auto& grid : grids)
    if (grid->getName() == grid_names::kDensity && grid->activeVoxelCount() > 0)
      saw_density_ = saw_density_ || openvdb::tools::minMax(openvdb::gridPtrCast<openvdb::FloatGrid>(grid)->tree()).max() > 0;
  GridMapping none;
  none.preset = GridPreset::kNone;
  return mediumOfGrids(std::move(grids), metadata_, none, path_);
}

void MediumSlabs::finish() const {
  if (!saw_density_) failEmptyDensity(path_);
}

}  // namespace vdbappear
