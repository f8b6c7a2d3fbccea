#include "libvdbappear/io/medium_slabs.h"

#include "libvdbappear/io/grid_presets.h"
#include "libvdbappear/io/mapped_grids.h"
#include "libvdbappear/io/mapped_pages.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_of_grids.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/io/vdb_read_error.h"
#include "libvdbappear/math/block_index.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <openvdb/tools/Count.h>
#include <openvdb/util/logging.h>

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
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

// The grid's leaf origins sorted by x, and its tiles as a grid of their own (null if none).
template <typename GridT>
void findPieces(const GridT& grid, std::vector<openvdb::Coord>& leaves, openvdb::GridBase::Ptr& tiles) {
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf->origin());
  std::stable_sort(leaves.begin(), leaves.end(), [](const auto& a, const auto& b) { return a.x() < b.x(); });
  typename GridT::Ptr found;
  auto tile = grid.tree().cbeginValueAll();
  tile.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) {
    if (!tile.isValueOn() && *tile == grid.background()) continue;
    if (!found) found = GridT::create(grid.background());
    found->tree().fill(tile.getBoundingBox(), *tile, tile.isValueOn());
  }
  tiles = found;
}

// The grid's part in [x0, x1): its leaves there moved out of `grid` (still on the file), its tiles
// cut to the slab.
template <typename GridT>
typename GridT::Ptr takeSlab(GridT& grid, const std::vector<openvdb::Coord>& leaves, const GridT* tiles,
                             const SlabRange& range) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  auto slab = GridT::create(grid.background());
  for (auto meta = grid.beginMeta(); meta != grid.endMeta(); ++meta) slab->insertMeta(meta->first, *meta->second);
  slab->setTransform(grid.transform().copy());
  auto first = std::lower_bound(leaves.begin(), leaves.end(), range.first, [](const auto& c, int x) { return c.x() < x; });
  for (; first != leaves.end() && first->x() < range.second; ++first)
    slab->tree().addLeaf(grid.tree().root().template stealNode<LeafT>(*first, grid.background(), false));
  if (!tiles) return slab;
  auto tile = tiles->tree().cbeginValueAll();
  tile.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) {
    if (!tile.isValueOn() && *tile == grid.background()) continue;
    openvdb::CoordBBox box;
    tile.getBoundingBox(box);
    box.min().x() = std::max(box.min().x(), range.first);
    box.max().x() = std::min(box.max().x(), range.second - 1);
    if (box.min().x() <= box.max().x()) slab->tree().fill(box, *tile, tile.isValueOn());
  }
  return slab;
}

// Every leaf of the slab read from the file now, in parallel (decompression dominates), so that a
// damaged file fails here, naming the grid.
template <typename GridT>
void loadLeaves(GridT& grid, const std::string& path) {
  try {
    openvdb::tree::LeafManager<typename GridT::TreeType> leaves(grid.tree());
    leaves.foreach([](typename GridT::TreeType::LeafNodeType& leaf, std::size_t) { leaf.buffer().data(); });
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: grid '{}': cannot be read ({})", path, grid.getName(), vdbReadError(e)));
  }
}

bool slabType(const openvdb::GridBase& grid) {
  return grid.apply<SlabGridTypes>([](const auto&) {});
}

// The bytes of each band's leaves, of the internal nodes they bring along and of its output leaves,
// and what stays in memory throughout (each leaf's node on the input file's side, and on the output's
// scratch files' side: io/spilled_medium.h), for one grid.
template <typename GridT>
void addGridBytes(const GridT& grid, const std::vector<openvdb::Coord>& leaves, const GridT* tiles, int band,
                  std::map<int, std::uint64_t>& band_bytes, std::uint64_t& resident_bytes) {
  using TreeT = typename GridT::TreeType;
  // An unread leaf: its node, masks and file reference, with the allocator's share (measured: 266
  // and 284 bytes a leaf for the 1024^3 twill's density and albedo read with delayed loading).
  constexpr std::uint64_t kOnFileLeafBytes = 288;
  const std::uint64_t bytes = leafBytesOf(grid);
  std::set<openvdb::Coord> blocks;                       // the output's leaves
  std::set<std::tuple<int, int, openvdb::Coord>> nodes;  // (band, level, internal node) a band's leaves need
  for (const openvdb::Coord& origin : leaves) {
    const int b = floorDiv(origin.x(), band);
    for (const int log2 : {7, 12})  // the two internal levels: 128^3 and 4096^3 voxels
      if (nodes.insert({b, log2, blockOf(origin, openvdb::Coord(1 << log2))}).second)
        band_bytes[b] += log2 == 7 ? kNode1Bytes<TreeT> : kNode2Bytes<TreeT>;
    band_bytes[b] += bytes;
    resident_bytes += kOnFileLeafBytes;
    if (blocks.insert(blockOf(origin, openvdb::Coord(band))).second) band_bytes[b] += bytes;  // its output leaf
  }
  if (tiles) {
    auto tile = tiles->tree().cbeginValueAll();
    tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {  // a tile's part in a band, as leaves
      if (!tile.isValueOn() && *tile == grid.background()) continue;
      const openvdb::CoordBBox box = tile.getBoundingBox();
      const std::uint64_t leaves_per_band =
          (std::uint64_t(box.dim().y()) * std::uint64_t(box.dim().z()) / 64 + 1) * std::uint64_t(band / 8 + 1);
      for (int b = floorDiv(box.min().x(), band); b <= floorDiv(box.max().x(), band); ++b) band_bytes[b] += leaves_per_band * bytes;
      for (auto c = blocksOf(box, openvdb::Coord(band)).begin(); c; ++c)
        if (blocks.insert(*c).second) band_bytes[(*c).x()] += bytes;  // blocks are bands along x
    }
  }
  resident_bytes += blocks.size() * kOnFileLeafBytes;  // the output's leaves, their values on disk
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

}  // namespace

MediumSlabs::MediumSlabs(const std::string& path, const GridMapping& mapping) : path_(path) {
  openvdb::initialize();
  // A damaged file fails the delayed open with a MediumError below; OpenVDB's own error log of it
  // (log4cplus, not configured here) would add a line that says only that no logger is configured.
  openvdb::logging::setLevel(openvdb::logging::Level::Fatal);
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw MediumError(fmt::format("{}: no such file", path));
  if (std::filesystem::is_directory(path, error)) throw MediumError(fmt::format("{}: is a directory", path));
  openvdb::io::File file(path);
  file.setCopyMaxBytes(0);  // map the file itself, not a private copy (the input is never modified)
  const std::vector<std::string> names = openGridNames(file, path, /*delay_load=*/true);
  metadata_ = file.getMetadata();
  for (const auto& name : names) {
    try {
      grids_.push_back(file.readGrid(name));
    } catch (const std::exception& e) {
      throw MediumError(fmt::format("{}: grid '{}': cannot be read ({})", path, name, vdbReadError(e)));
    }
  }
  // A mapping makes grids from whole source grids: such a file is read whole (readMedium).
  const auto odd = std::find_if(grids_.begin(), grids_.end(), [](const auto& g) { return !slabType(*g); });
  if (odd != grids_.end()) {
    why_not_ = fmt::format("grid '{}' holds {} values", (*odd)->getName(), (*odd)->valueType());
  } else if (!mapping.rules.empty()) {
    why_not_ = "--grid rules apply to it";
  } else if (!presetRules(grids_, mapping.preset, {}).empty()) {
    why_not_ = "a preset maps its grids (--from none reads them as they are)";
  } else {
    notes_ = applyGridMapping(grids_, mapping, path).notes;  // names and topology only: nothing is read
  }
  pieces_.resize(grids_.size());
  for (std::size_t i = 0; i < grids_.size() && !why_not_; ++i)
    if (isVoxelIndexed(grids_[i]->getName()))
      grids_[i]->apply<SlabGridTypes>([&](const auto& grid) { findPieces(grid, pieces_[i].leaves, pieces_[i].tiles); });
}

MediumSlabs::Plan MediumSlabs::plan(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes) const {
  std::map<int, std::uint64_t> band_bytes;  // band index -> bytes of its leaves, every voxel grid
  Plan plan;
  for (std::size_t i = 0; i < grids_.size(); ++i)
    if (isVoxelIndexed(grids_[i]->getName()))
      grids_[i]->apply<SlabGridTypes>([&](const auto& grid) {
        using GridT = std::decay_t<decltype(grid)>;
        addGridBytes(grid, pieces_[i].leaves, static_cast<const GridT*>(pieces_[i].tiles.get()), band, band_bytes,
                     plan.resident_bytes);
      });
  for (const auto& entry : band_bytes) plan.largest_band_bytes = std::max(plan.largest_band_bytes, entry.second);
  const std::uint64_t free_bytes = memory_bytes > plan.resident_bytes ? memory_bytes - plan.resident_bytes : 0;
  if (plan.largest_band_bytes > free_bytes) return plan;  // no slabs: one band does not fit
  plan.slabs = packSlabs(band_bytes, band, std::min(free_bytes, std::max(slab_target_bytes, plan.largest_band_bytes)));
  return plan;
}

MediumPtr MediumSlabs::slab(const SlabRange& range) {
  releaseMappedPages({path_});  // the slabs before this one are read and freed
  openvdb::GridPtrVec grids;
  for (std::size_t i = 0; i < grids_.size(); ++i) {
    if (!isVoxelIndexed(grids_[i]->getName())) {
      grids.push_back(grids_[i]->deepCopyGrid());
      continue;
    }
    grids_[i]->apply<SlabGridTypes>([&](auto& grid) {
      using GridT = std::decay_t<decltype(grid)>;
      auto part = takeSlab(grid, pieces_[i].leaves, static_cast<const GridT*>(pieces_[i].tiles.get()), range);
      loadLeaves(*part, path_);
      grids.push_back(part);
    });
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
