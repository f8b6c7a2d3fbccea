#include "libvdbappear/modularity/block_moves.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <functional>
#include <limits>

namespace vdbappear {

using openvdb::Coord;

namespace {

Coord scaled(const Coord& b, const Coord& block) { return Coord(b.x() * block.x(), b.y() * block.y(), b.z() * block.z()); }

// Writes one grid's moved values through an accessor, remembering the last block looked up (values
// come in tree order, so runs of voxels share a block).
template <typename GridT>
class GridMover {
 public:
  using ValueT = typename GridT::ValueType;

  GridMover(const GridT& source, const BlockMoves& moves, const std::string& file)
      : source_(source), moves_(moves), file_(file), moved_(source.copyWithNewTree()), out_(moved_->getAccessor()) {}

  typename GridT::Ptr run() {
    for (auto it = source_.cbeginValueOn(); it; ++it) {
      if (it.isVoxelValue()) {
        put(it.getCoord(), *it);
      } else {  // an active tile: every voxel it covers
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        for (const Coord& ijk : box) put(ijk, *it);
      }
    }
    return moved_;
  }

 private:
  void put(const Coord& ijk, const ValueT& value) {
    const Coord b = blockOf(ijk, moves_.block);
    if (b != cached_block_ || !copies_) lookUp(ijk, b);
    const Coord local = ijk - scaled(b, moves_.block);
    for (const Coord& d : *copies_) out_.setValueOn(scaled(d, moves_.block) + local, value);
  }

  void lookUp(const Coord& ijk, const Coord& b) {
    const auto found = moves_.destinations.find(b);
    if (found == moves_.destinations.end())
      throw MediumError(fmt::format("{}: grid '{}': active voxel at ({},{},{}) lies in block ({},{},{}), which holds no "
                                    "exemplar", file_, source_.getName(), ijk.x(), ijk.y(), ijk.z(), b.x(), b.y(), b.z()));
    cached_block_ = b;
    copies_ = &found->second;
  }

  const GridT& source_;
  const BlockMoves& moves_;
  const std::string& file_;
  typename GridT::Ptr moved_;
  typename GridT::Accessor out_;
  Coord cached_block_ = Coord(std::numeric_limits<int>::max());
  const std::vector<Coord>* copies_ = nullptr;
};

template <typename GridT>
typename GridT::Ptr moveGrid(const GridT& grid, const BlockMoves& moves, const std::string& file) {
  return GridMover<GridT>(grid, moves, file).run();
}

using MovableGrids = openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid, openvdb::Int32Grid, openvdb::Int64Grid,
                                       openvdb::Vec3SGrid, openvdb::Vec3DGrid, openvdb::Vec3IGrid, openvdb::BoolGrid>;

openvdb::GridBase::Ptr moveOtherGrid(const openvdb::GridBase& grid, const BlockMoves& moves, const std::string& file) {
  if (grid.getName() == grid_names::kPhaseTable || isBlockIndexedGridName(grid.getName())) return grid.deepCopyGrid();
  openvdb::GridBase::Ptr moved;
  const bool known = grid.apply<MovableGrids>([&](const auto& typed) { moved = moveGrid(typed, moves, file); });
  if (!known)
    throw MediumError(fmt::format("{}: grid '{}': values of type {} cannot be moved block by block", file,
                                  grid.getName(), grid.valueType()));
  return moved;
}

}  // namespace

std::map<Coord, std::uint64_t> activeVoxelsPerBlock(const openvdb::FloatGrid& density, const Coord& block) {
  std::map<Coord, std::uint64_t> voxels;
  for (auto v = density.cbeginValueOn(); v; ++v) voxels[blockOf(v.getCoord(), block)] += v.getVoxelCount();
  return voxels;
}

MediumPtr moveBlocks(const Medium& source, const BlockMoves& moves) {
  auto out = std::make_shared<Medium>();
  out->metadata = source.metadata;
  out->source = source.source;
  out->other_grids.resize(source.other_grids.size());
  const std::string& file = source.source;
  // One task per grid: the grids are independent, each written through its own accessor.
  std::vector<std::function<void()>> tasks;
  tasks.push_back([&] { out->density = moveGrid(*source.density, moves, file); });
  if (source.albedo) tasks.push_back([&] { out->albedo = moveGrid(*source.albedo, moves, file); });
  if (source.sggx_diag) tasks.push_back([&] { out->sggx_diag = moveGrid(*source.sggx_diag, moves, file); });
  if (source.sggx_offdiag) tasks.push_back([&] { out->sggx_offdiag = moveGrid(*source.sggx_offdiag, moves, file); });
  if (source.hg_g) tasks.push_back([&] { out->hg_g = moveGrid(*source.hg_g, moves, file); });
  for (std::size_t i = 0; i < source.other_grids.size(); ++i)
    tasks.push_back([&, i] { out->other_grids[i] = moveOtherGrid(*source.other_grids[i], moves, file); });
  tbb::parallel_for(std::size_t(0), tasks.size(), [&](std::size_t i) { tasks[i](); });
  return out;
}

}  // namespace vdbappear
