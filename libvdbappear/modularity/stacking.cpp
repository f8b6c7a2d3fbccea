#include "libvdbappear/modularity/stacking.h"

#include "libvdbappear/modularity/block_moves.h"
#include "libvdbappear/modularity/exemplar_set.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/hash_random.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace vdbappear {

using openvdb::Coord;

namespace {

Coord slotOf(int s, const BlockCounts& shape) {
  return Coord(s % shape[0], (s / shape[0]) % shape[1], s / (shape[0] * shape[1]));
}

std::vector<int> identityOrder(int count) {
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  return order;
}

// Fisher-Yates with counter-based draws: the same order for a seed on every machine.
std::vector<int> shuffled(int count, std::uint64_t seed) {
  std::vector<int> order = identityOrder(count);
  for (int i = count - 1; i > 0; --i)
    std::swap(order[std::size_t(i)], order[std::size_t(hashKeys(seed, {7, i}) % std::uint64_t(i + 1))]);
  return order;
}

openvdb::Int32Grid::Ptr stackingGrid(const std::vector<int>& order, const BlockCounts& shape,
                                     const openvdb::math::Transform::Ptr& transform) {
  auto grid = openvdb::Int32Grid::create(0);
  grid->setName(grid_names::kExemplarStacking);
  grid->setTransform(transform);
  auto accessor = grid->getAccessor();
  for (std::size_t s = 0; s < order.size(); ++s) accessor.setValueOn(slotOf(int(s), shape), order[s]);
  return grid;
}

// Stacked block -> exemplar, every exemplar exactly once.
std::map<Coord, int> placementOf(const Medium& stacked, int count) {
  const auto grid = findOtherGrid<openvdb::Int32Grid>(stacked, grid_names::kExemplarStacking);
  if (!grid)
    throw MediumError(fmt::format("{}: no grid 'exemplar_stacking': the placement of the exemplars is unknown (give the "
                                  "output of vdb_exemplar_stack stack, or of the pipeline run on it)", stacked.source));
  std::map<Coord, int> placement;
  std::vector<int> seen(static_cast<std::size_t>(count), 0);
  for (auto v = grid->cbeginValueOn(); v; ++v) {
    if (!v.isVoxelValue())
      throw MediumError(fmt::format("{}: grid 'exemplar_stacking': a tile where blocks are single voxels", stacked.source));
    placement[v.getCoord()] = *v;
    ++seen[std::size_t(*v)];  // ids were checked against exemplar_count when the medium was read
  }
  for (int e = 0; e < count; ++e)
    if (seen[std::size_t(e)] != 1)
      throw MediumError(fmt::format("{}: grid 'exemplar_stacking': exemplar {} is placed {} times; each of 0..{} must "
                                    "be placed once", stacked.source, e, seen[std::size_t(e)], count - 1));
  return placement;
}

}  // namespace

BlockCounts stackShape(int count, const BlockCounts& block) {
  const bool sheets = 2 * block[2] < std::min(block[0], block[1]);
  BlockCounts best{count, 1, 1};
  double best_area = std::numeric_limits<double>::infinity();
  for (int nx = 1; nx <= count; ++nx)
    for (int ny = 1; nx * ny <= count || (sheets && ny <= count); ++ny) {
      if (sheets && (nx * ny < count || (nx - 1) * ny >= count)) continue;  // one layer, no empty column
      if (sheets && nx * (ny - 1) >= count) break;                           // ... and no empty row
      const int nz = (count + nx * ny - 1) / (nx * ny);
      const double a = double(nx) * block[0], b = double(ny) * block[1], c = double(nz) * block[2];
      // A layer of sheets: the least perimeter (the most square), then the fewest slots; a volume:
      // the least surface.
      const double cost = sheets ? a + b + 1e-6 * nx * ny : a * b + b * c + a * c;
      if (cost < best_area - 1e-9) best_area = cost, best = {nx, ny, nz};
    }
  return best;
}

std::vector<int> stackOrder(int count, const StackOptions& options) {
  switch (options.order) {
    case StackOptions::Order::Random: return shuffled(count, options.seed);
    case StackOptions::Order::Sorted: return identityOrder(count);
    case StackOptions::Order::Given: break;
  }
  std::vector<int> sorted = options.permutation;
  std::sort(sorted.begin(), sorted.end());
  if (sorted != identityOrder(count))
    throw std::invalid_argument(fmt::format("--order: {} ids given; need each of 0..{} exactly once",
                                            options.permutation.size(), count - 1));
  return options.permutation;
}

BlockCounts stackShapeFor(const Medium& blocks, const StackOptions& options) {
  const ExemplarSet set = readExemplarSet(blocks, ExemplarKind::Blocks);
  if (options.shape[0] <= 0) return stackShape(set.count, {set.block.x(), set.block.y(), set.block.z()});
  const BlockCounts& shape = options.shape;
  if (double(shape[0]) * shape[1] * shape[2] < set.count)
    throw std::invalid_argument(fmt::format("--shape {}x{}x{}: {} slots for {} exemplars", shape[0], shape[1], shape[2],
                                            double(shape[0]) * shape[1] * shape[2], set.count));
  return shape;
}

MediumPtr stackExemplars(const Medium& blocks, const StackOptions& options) {
  const ExemplarSet set = readExemplarSet(blocks, ExemplarKind::Blocks);
  const BlockCounts shape = stackShapeFor(blocks, options);
  const std::vector<int> order = stackOrder(set.count, options);
  BlockMoves moves{set.block, {}};
  for (std::size_t s = 0; s < order.size(); ++s) moves.destinations[Coord(order[s], 0, 0)] = {slotOf(int(s), shape)};
  MediumPtr stacked = moveBlocks(blocks, moves);
  stacked->other_grids.push_back(stackingGrid(order, shape, stacked->density->transformPtr()));
  writeExemplarSet(*stacked, {set.count, set.block, ExemplarKind::Stacked, 1, exemplarSetName(blocks)});
  return stacked;
}

MediumPtr splitStacked(const Medium& stacked) {
  const ExemplarSet set = readExemplarSet(stacked, ExemplarKind::Stacked);
  BlockMoves moves{set.block, {}};
  for (const auto& [slot, e] : placementOf(stacked, set.count)) moves.destinations[slot] = {Coord(e, 0, 0)};
  MediumPtr blocks = moveBlocks(stacked, moves);
  removeOtherGrid(*blocks, grid_names::kExemplarStacking);
  writeExemplarSet(*blocks, {set.count, set.block, ExemplarKind::Blocks, 1, set.name});
  return blocks;
}

}  // namespace vdbappear
