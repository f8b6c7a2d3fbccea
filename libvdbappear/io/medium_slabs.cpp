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
#include <array>
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

// A cell: band index along x, then the cell's index along y and z (cells of `cellSize(band)` voxels).
using Cell = std::array<int, 3>;

Cell cellOf(const openvdb::Coord& ijk, int band) {
  const int cell = cellSize(band);
  return {floorDiv(ijk.x(), band), floorDiv(ijk.y(), cell), floorDiv(ijk.z(), cell)};
}

// The bytes of each cell's leaves, of the internal nodes they bring along and of its output leaves,
// and what stays in memory throughout (each leaf's node on the input file's side, and on the output's
// scratch files' side: io/spilled_medium.h), for one grid, and for `extra_outputs` output grids of
// Vec3s values (the most a contract grid takes) with its output's topology.
template <typename GridT>
void addGridBytes(const GridT& grid, const SlabTreeIndex& index, int band, int extra_outputs,
                  std::map<Cell, std::uint64_t>& cell_bytes, std::uint64_t& resident_bytes) {
  using TreeT = typename GridT::TreeType;
  // An output leaf whose values wait on disk: its node, masks and file reference, with the
  // allocator's share (measured: 266 and 284 bytes a leaf for the 1024^3 twill's density and albedo
  // read with OpenVDB's delayed loading).
  constexpr std::uint64_t kOnFileLeafBytes = 288;
  const std::uint64_t bytes = leafBytesOf(grid);
  const std::uint64_t output_bytes = bytes + std::uint64_t(extra_outputs) * leafBytesOf(openvdb::Vec3SGrid());
  const int cell = cellSize(band);
  std::set<openvdb::Coord> blocks;                        // the output's leaves
  std::set<std::tuple<Cell, int, openvdb::Coord>> nodes;  // (cell, level, internal node) a cell's leaves need
  const auto addBlock = [&](const openvdb::Coord& block) {  // an output leaf, by its index in band-sized blocks
    if (blocks.insert(block).second) cell_bytes[cellOf(openvdb::Coord(block.x() * band, block.y() * band, block.z() * band), band)] += output_bytes;
  };
  index.forEachLeaf([&](const openvdb::Coord& origin) {
    const Cell c = cellOf(origin, band);
    for (const int log2 : {7, 12})  // the two internal levels: 128^3 and 4096^3 voxels
      if (nodes.insert({c, log2, blockOf(origin, openvdb::Coord(1 << log2))}).second)
        cell_bytes[c] += log2 == 7 ? kNode1Bytes<TreeT> : kNode2Bytes<TreeT>;
    cell_bytes[c] += bytes;
    addBlock(blockOf(origin, openvdb::Coord(band)));
  });
  resident_bytes += index.memoryBytes();
  if (const auto* tiles = static_cast<const GridT*>(index.tiles().get())) {
    auto tile = tiles->tree().cbeginValueAll();
    tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {  // a tile's part in each cell, as leaves
      if (!tile.isValueOn() && *tile == grid.background()) continue;
      const openvdb::CoordBBox box = tile.getBoundingBox();
      const Cell first = cellOf(box.min(), band), last = cellOf(box.max(), band);
      const openvdb::CoordBBox cells(openvdb::Coord(first[0], first[1], first[2]), openvdb::Coord(last[0], last[1], last[2]));
      for (auto c = cells.begin(); c; ++c) {
        openvdb::CoordBBox part(openvdb::Coord((*c).x() * band, (*c).y() * cell, (*c).z() * cell),
                                openvdb::Coord((*c).x() * band + band - 1, (*c).y() * cell + cell - 1, (*c).z() * cell + cell - 1));
        part.intersect(box);
        cell_bytes[{(*c).x(), (*c).y(), (*c).z()}] +=
            (std::uint64_t(part.dim().y()) * std::uint64_t(part.dim().z()) / 64 + 1) * std::uint64_t(band / 8 + 1) * bytes;
      }
      for (auto c = blocksOf(box, openvdb::Coord(band)).begin(); c; ++c) addBlock(*c);
    }
  }
  resident_bytes += blocks.size() * kOnFileLeafBytes * (1 + extra_outputs);  // the output's leaves, their values on disk
}

// Runs [first, last] of consecutive indices whose sizes sum to at most `limit` (an index alone may exceed it).
std::vector<std::pair<int, int>> consecutiveRuns(const std::map<int, std::uint64_t>& sizes, std::uint64_t limit) {
  std::vector<std::pair<int, int>> runs;
  std::uint64_t used = 0;
  for (const auto& [index, size] : sizes) {
    if (!runs.empty() && runs.back().second == index - 1 && used + size <= limit) {
      runs.back().second = index;
      used += size;
    } else {
      runs.push_back({index, index});
      used = size;
    }
  }
  return runs;
}

// Pieces of at most `limit` bytes where a cell allows: consecutive bands packed into slabs; a band
// over the limit split into runs of rows of cells along y; a row over it into runs of cells along z.
std::vector<openvdb::CoordBBox> packPieces(const std::map<Cell, std::uint64_t>& cell_bytes, int band, std::uint64_t limit) {
  const int cell = cellSize(band);
  const int lo = openvdb::Coord::min().x(), hi = openvdb::Coord::max().x();
  std::map<int, std::uint64_t> band_bytes;
  std::map<int, std::map<int, std::uint64_t>> row_bytes;                  // band -> row -> bytes
  std::map<std::pair<int, int>, std::map<int, std::uint64_t>> row_cells;  // (band, row) -> z cell -> bytes
  for (const auto& [c, bytes] : cell_bytes) {
    band_bytes[c[0]] += bytes;
    row_bytes[c[0]][c[1]] += bytes;
    row_cells[{c[0], c[1]}][c[2]] += bytes;
  }
  std::vector<openvdb::CoordBBox> pieces;
  for (const auto& [b0, b1] : consecutiveRuns(band_bytes, limit)) {
    if (b0 < b1 || band_bytes[b0] <= limit) {
      pieces.emplace_back(openvdb::Coord(b0 * band, lo, lo), openvdb::Coord(b1 * band + band - 1, hi, hi));
      continue;
    }
    const int x0 = b0 * band, x1 = x0 + band - 1;
    for (const auto& [y0, y1] : consecutiveRuns(row_bytes[b0], limit)) {
      if (y0 < y1 || row_bytes[b0][y0] <= limit) {
        pieces.emplace_back(openvdb::Coord(x0, y0 * cell, lo), openvdb::Coord(x1, y1 * cell + cell - 1, hi));
        continue;
      }
      for (const auto& [z0, z1] : consecutiveRuns(row_cells[{b0, y0}], limit))
        pieces.emplace_back(openvdb::Coord(x0, y0 * cell, z0 * cell), openvdb::Coord(x1, y0 * cell + cell - 1, z1 * cell + cell - 1));
    }
  }
  return pieces;
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

int cellSize(int band) { return band * ((127 + band) / band); }

std::string pieceName(const openvdb::CoordBBox& piece) {
  std::string name = fmt::format("x = {}..{}", piece.min().x(), piece.max().x());
  if (piece.min().y() > openvdb::Coord::min().y() || piece.max().y() < openvdb::Coord::max().y())
    name += fmt::format(", y = {}..{}", piece.min().y(), piece.max().y());
  if (piece.min().z() > openvdb::Coord::min().z() || piece.max().z() < openvdb::Coord::max().z())
    name += fmt::format(", z = {}..{}", piece.min().z(), piece.max().z());
  return name;
}

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
  std::map<Cell, std::uint64_t> cell_bytes;  // cell -> bytes of its leaves, every voxel grid
  Plan plan;
  for (std::size_t i = 0; i < grids_.size(); ++i)
    if (indices_[i])
      grids_[i]->apply<SlabGridTypes>(
          [&](const auto& grid) {
            const int extra = grid.getName() == grid_names::kDensity ? extra_output_grids : 0;
            addGridBytes(grid, *indices_[i], band, extra, cell_bytes, plan.resident_bytes);
          });
  for (const auto& entry : cell_bytes) plan.largest_cell_bytes = std::max(plan.largest_cell_bytes, entry.second);
  const std::uint64_t free_bytes = memory_bytes > plan.resident_bytes ? memory_bytes - plan.resident_bytes : 0;
  if (plan.largest_cell_bytes > free_bytes) return plan;  // no slabs: one cell does not fit
  plan.slabs = packPieces(cell_bytes, band, std::min(free_bytes, std::max(slab_target_bytes, plan.largest_cell_bytes)));
  return plan;
}

MediumSlabs::Plan MediumSlabs::planWithin(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes,
                                          int extra_output_grids) const {
  Plan fitted = plan(band, memory_bytes, slab_target_bytes, extra_output_grids);
  if (fitted.slabs.empty() && fitted.largest_cell_bytes > 0) {
    const double needed = double(fitted.resident_bytes + fitted.largest_cell_bytes) / 1e9;
    const int cell = cellSize(band);
    throw MediumError(fmt::format("{}: a memory budget of {:.3g} GB is too small: one piece of {} x {} x {} voxels "
                                  "needs {:.3g} GB with what stays in memory (--memory {:.3g} or more)",
                                  path_, double(memory_bytes) / 1e9, band, cell, cell, needed, roundedUp(needed)));
  }
  return fitted;
}

MediumPtr MediumSlabs::slab(const openvdb::CoordBBox& box) {
  file_->releasePages();
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
