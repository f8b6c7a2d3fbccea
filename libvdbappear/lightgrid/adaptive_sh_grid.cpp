#include "libvdbappear/lightgrid/adaptive_sh_grid.h"

#include "libvdbappear/lightgrid/zonal_factorisation.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

constexpr int kMaxLevel = 12;

}  // namespace

// 4 bits of level and 20 bits per index (indices up to 2^20 - 1 at any level).
std::uint64_t AdaptiveShGrid::key(int level, std::int64_t i, std::int64_t j, std::int64_t k) {
  return std::uint64_t(level) << 60 | std::uint64_t(i) << 40 | std::uint64_t(j) << 20 | std::uint64_t(k);
}

std::uint64_t AdaptiveShGrid::nodeKey(int level, std::int64_t i, std::int64_t j, std::int64_t k) const {
  while (level > 0 && i % 2 == 0 && j % 2 == 0 && k % 2 == 0) {
    --level;
    i /= 2;
    j /= 2;
    k /= 2;
  }
  return key(level, i, j, k);
}

Vec3 AdaptiveShGrid::nodePosition(int level, std::int64_t i, std::int64_t j, std::int64_t k) const {
  return origin_ + spacing(level) * Vec3(double(i), double(j), double(k));
}

const ShLighting& AdaptiveShGrid::corner(const Cell& c, int n) const {
  return nodes_[node_index_.at(nodeKey(c.level, c.i + (n & 1), c.j + (n >> 1 & 1), c.k + (n >> 2 & 1)))];
}

std::size_t AdaptiveShGrid::cellCount(int level) const {
  return level < levels() ? cells_per_level_[level] : 0;
}

double AdaptiveShGrid::errorEstimate(const Cell& c) const {
  const double h = spacing(c.level);
  const Vec3 size = Vec3::Constant(h), centre = Vec3::Constant(h / 2);
  const CellWeights hermite = cellWeights(CellInterpolation::kHermite, centre, size);
  const CellWeights trilinear = cellWeights(CellInterpolation::kTrilinear, centre, size);
  const ShLighting* corners[8];
  for (int n = 0; n < 8; ++n) corners[n] = &corner(c, n);
  double worst = 0;
  for (int s = 0; s < shCount(lmax_); ++s) {
    Vec3 difference = Vec3::Zero();
    for (int n = 0; n < 8; ++n)
      difference += (hermite.value[n] - trilinear.value[n]) * corners[n]->coeffs[s] + corners[n]->gradients[s] * hermite.gradient[n];
    worst = std::max(worst, difference.cwiseAbs().maxCoeff());
  }
  return worst;
}

void AdaptiveShGrid::evaluateNodes(const std::vector<std::uint64_t>& keys, const std::vector<Vec3>& positions,
                                   const std::vector<PolygonLight>& lights, const ZonalFactorisation& zh) {
  const std::size_t first = nodes_.size();
  nodes_.resize(first + keys.size());
  tbb::parallel_for(std::size_t(0), keys.size(), [&](std::size_t n) { nodes_[first + n] = shLighting(lights, positions[n], zh); });
  for (std::size_t n = 0; n < keys.size(); ++n) node_index_[keys[n]] = std::uint32_t(first + n);
}

AdaptiveShGrid AdaptiveShGrid::build(const std::vector<PolygonLight>& lights, int lmax, const Vec3& lo, const Vec3& hi,
                                     const AdaptiveGridOptions& options, ProgressBar* progress) {
  if (options.base_resolution < 2) throw std::invalid_argument("adaptive SH grid: the base resolution must be at least 2 nodes");
  if (options.max_level < 0 || options.max_level > kMaxLevel)
    throw std::invalid_argument("adaptive SH grid: max_level must be in 0..12");
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0) || !((hi - lo).array() >= 0).all()) throw std::invalid_argument("adaptive SH grid: the box is empty");
  AdaptiveShGrid grid;
  grid.lmax_ = lmax;
  grid.origin_ = lo;
  grid.base_spacing_ = extent / (options.base_resolution - 1);
  for (int a = 0; a < 3; ++a) grid.base_cells_[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / grid.base_spacing_ - 1e-9)));
  if (std::int64_t(std::max({grid.base_cells_[0], grid.base_cells_[1], grid.base_cells_[2]})) << options.max_level >= (1 << 20))
    throw std::invalid_argument("adaptive SH grid: too many cells along an axis");
  const ZonalFactorisation zh(lmax);

  // Level 0: every node of the base grid.
  std::vector<Cell> cells;
  {
    std::vector<std::uint64_t> keys;
    std::vector<Vec3> positions;
    for (int k = 0; k <= grid.base_cells_[2]; ++k)
      for (int j = 0; j <= grid.base_cells_[1]; ++j)
        for (int i = 0; i <= grid.base_cells_[0]; ++i) {
          keys.push_back(key(0, i, j, k));
          positions.push_back(grid.nodePosition(0, i, j, k));
        }
    grid.evaluateNodes(keys, positions, lights, zh);
    for (int k = 0; k < grid.base_cells_[2]; ++k)
      for (int j = 0; j < grid.base_cells_[1]; ++j)
        for (int i = 0; i < grid.base_cells_[0]; ++i) cells.push_back({0, i, j, k});
  }
  double scale = 0;
  for (const ShLighting& node : grid.nodes_) scale = std::max(scale, node.coeffs[0].cwiseAbs().maxCoeff());
  const double threshold = options.tolerance * (scale > 0 ? scale : 1.0);
  if (progress) progress->setTotal(options.max_level + 1);

  for (int level = 0;; ++level) {
    grid.cells_per_level_.push_back(cells.size());
    if (progress) progress->advance();
    if (level == options.max_level) break;
    std::vector<double> error(cells.size());
    tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t c) { error[c] = grid.errorEstimate(cells[c]); });
    // Split the worst cells first, within the node budget.
    std::vector<std::size_t> order;
    for (std::size_t c = 0; c < cells.size(); ++c)
      if (error[c] > threshold) order.push_back(c);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return error[a] > error[b] || (error[a] == error[b] && a < b); });
    std::vector<Cell> children;
    std::vector<std::uint64_t> keys;
    std::vector<Vec3> positions;
    std::unordered_set<std::uint64_t> pending;
    for (std::size_t c : order) {
      const Cell& cell = cells[c];
      std::vector<std::uint64_t> cell_keys;
      std::vector<Vec3> cell_positions;
      for (int di = 0; di <= 2; ++di)
        for (int dj = 0; dj <= 2; ++dj)
          for (int dk = 0; dk <= 2; ++dk) {
            const std::int64_t i = 2 * std::int64_t(cell.i) + di, j = 2 * std::int64_t(cell.j) + dj, k = 2 * std::int64_t(cell.k) + dk;
            const std::uint64_t node = grid.nodeKey(level + 1, i, j, k);
            if (grid.node_index_.count(node) || pending.count(node)) continue;
            cell_keys.push_back(node);
            cell_positions.push_back(grid.nodePosition(level + 1, i, j, k));
          }
      if (grid.nodes_.size() + keys.size() + cell_keys.size() > options.max_nodes) break;
      for (std::size_t n = 0; n < cell_keys.size(); ++n) {
        pending.insert(cell_keys[n]);
        keys.push_back(cell_keys[n]);
        positions.push_back(cell_positions[n]);
      }
      grid.split_.insert(key(cell.level, cell.i, cell.j, cell.k));
      for (int n = 0; n < 8; ++n)
        children.push_back({level + 1, 2 * cell.i + (n & 1), 2 * cell.j + (n >> 1 & 1), 2 * cell.k + (n >> 2 & 1)});
    }
    if (children.empty()) break;
    grid.evaluateNodes(keys, positions, lights, zh);
    cells = std::move(children);
  }
  if (progress) progress->finish();
  return grid;
}

void AdaptiveShGrid::interpolate(const Vec3& x, CellInterpolation method, std::vector<Vec3>& out) const {
  if (!x.allFinite()) {
    out.assign(shCount(lmax_), Vec3::Zero());
    return;
  }
  // The base cell holding x (clamped into the box), then down the split cells.
  const Vec3 local = (x - origin_) / base_spacing_;
  Cell cell{0, 0, 0, 0};
  int* index[3] = {&cell.i, &cell.j, &cell.k};
  Vec3 t;
  for (int a = 0; a < 3; ++a) {
    t[a] = std::clamp(local[a], 0.0, double(base_cells_[a]));
    *index[a] = std::min(int(t[a]), base_cells_[a] - 1);
  }
  while (split_.count(key(cell.level, cell.i, cell.j, cell.k))) {
    const Vec3 fine = t * double(1 << (cell.level + 1));
    const auto child = [&](double f, int parent) { return std::clamp(int(f), 2 * parent, 2 * parent + 1); };
    cell = {cell.level + 1, child(fine.x(), cell.i), child(fine.y(), cell.j), child(fine.z(), cell.k)};
  }
  const double h = spacing(cell.level);
  const Vec3 p = (t * double(1 << cell.level) - Vec3(cell.i, cell.j, cell.k)) * h;
  const CellWeights w = cellWeights(method, p, Vec3::Constant(h));
  out.assign(shCount(lmax_), Vec3::Zero());
  for (int n = 0; n < 8; ++n) {
    const ShLighting& c = corner(cell, n);
    for (std::size_t s = 0; s < out.size(); ++s) out[s] += w.value[n] * c.coeffs[s] + c.gradients[s] * w.gradient[n];
  }
}

ShLattice AdaptiveShGrid::lattice() const {
  const int deepest = levels() - 1;
  return {origin_, spacing(deepest), deepest};
}

void AdaptiveShGrid::forEachNode(const std::function<void(const LatticeIndex&, const ShLighting&)>& visit) const {
  const int deepest = levels() - 1;
  std::vector<std::pair<LatticeIndex, std::uint32_t>> sorted;  // a fixed order, whatever the hash map's
  for (const auto& [node_key, index] : node_index_) {
    const int level = int(node_key >> 60);
    const std::int64_t scale = std::int64_t(1) << (deepest - level);
    const std::int64_t i = std::int64_t(node_key >> 40 & 0xFFFFF), j = std::int64_t(node_key >> 20 & 0xFFFFF), k = std::int64_t(node_key & 0xFFFFF);
    sorted.push_back({{i * scale, j * scale, k * scale}, index});
  }
  std::sort(sorted.begin(), sorted.end());
  for (const auto& [at, index] : sorted) visit(at, nodes_[index]);
}

bool AdaptiveShGrid::hasCorners(const Cell& c) const {
  for (int n = 0; n < 8; ++n)
    if (!node_index_.count(nodeKey(c.level, c.i + (n & 1), c.j + (n >> 1 & 1), c.k + (n >> 2 & 1)))) return false;
  return true;
}

void AdaptiveShGrid::indexCells() {
  split_.clear();
  cells_per_level_.clear();
  std::vector<Cell> cells;
  for (int k = 0; k < base_cells_[2]; ++k)
    for (int j = 0; j < base_cells_[1]; ++j)
      for (int i = 0; i < base_cells_[0]; ++i) cells.push_back({0, i, j, k});
  while (!cells.empty()) {
    cells_per_level_.push_back(cells.size());
    std::vector<Cell> children;
    for (const Cell& c : cells) {
      if (!hasCorners(c))
        throw std::invalid_argument(fmt::format("adaptive SH grid: cell ({}, {}, {}) of level {} lacks a corner node", c.i, c.j, c.k, c.level));
      if (!node_index_.count(nodeKey(c.level + 1, 2 * std::int64_t(c.i) + 1, 2 * std::int64_t(c.j) + 1, 2 * std::int64_t(c.k) + 1))) continue;
      split_.insert(key(c.level, c.i, c.j, c.k));
      for (int n = 0; n < 8; ++n) children.push_back({c.level + 1, 2 * c.i + (n & 1), 2 * c.j + (n >> 1 & 1), 2 * c.k + (n >> 2 & 1)});
    }
    cells = std::move(children);
  }
}

AdaptiveShGrid AdaptiveShGrid::fromNodes(int lmax, const ShLattice& lattice, std::vector<std::pair<LatticeIndex, ShLighting>> nodes) {
  if (lattice.levels < 0 || lattice.levels > kMaxLevel) throw std::invalid_argument("adaptive SH grid: levels must be in 0..12");
  AdaptiveShGrid grid;
  grid.lmax_ = lmax;
  grid.origin_ = lattice.origin;
  grid.base_spacing_ = lattice.spacing * double(1 << lattice.levels);
  const std::int64_t step = std::int64_t(1) << lattice.levels;
  std::int64_t top[3] = {0, 0, 0};
  for (const auto& [at, node] : nodes)
    for (int a = 0; a < 3; ++a) {
      if (at[a] < 0 || at[a] >= (std::int64_t(1) << 20)) throw std::invalid_argument("adaptive SH grid: a node lies outside the lattice");
      top[a] = std::max(top[a], at[a]);
    }
  for (int a = 0; a < 3; ++a) {
    if (top[a] % step != 0 || top[a] == 0) throw std::invalid_argument("adaptive SH grid: the nodes do not end on a base node");
    grid.base_cells_[a] = int(top[a] / step);
  }
  // Every base node must be present: fewer nodes than that cannot make a grid (and a hand-made file
  // with two far-apart nodes must not make us list a huge number of base cells).
  if (double(grid.base_cells_[0] + 1) * (grid.base_cells_[1] + 1) * (grid.base_cells_[2] + 1) > double(nodes.size()))
    throw std::invalid_argument("adaptive SH grid: fewer nodes than base nodes (a base node is missing)");
  grid.nodes_.reserve(nodes.size());
  for (auto& [at, node] : nodes) {
    grid.node_index_[grid.nodeKey(lattice.levels, at[0], at[1], at[2])] = std::uint32_t(grid.nodes_.size());
    grid.nodes_.push_back(std::move(node));
  }
  grid.indexCells();
  return grid;
}

}  // namespace vdbappear
