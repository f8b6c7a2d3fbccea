#pragma once
// A sparse adaptive SH light grid: a uniform base grid whose cells split in eight, level by level,
// where a gradient-based error estimate is large (in the spirit of the valid domains of irradiance
// caching; the dissertation, §5.7.3, leaves multi-level grids as future work).
//
// Error estimate of a cell, from its corner values and gradients only: the largest difference, over
// every coefficient and channel, between the tricubic Hermite and the trilinear interpolant at the
// cell's centre. Trilinear ignores the gradients, so the difference measures how far the corners'
// gradients disagree with a linear variation: small where the lighting is smooth at the cell's scale,
// large near lights and at grazing angles. A cell splits when the estimate exceeds `tolerance`
// times the largest |L_00| of the base nodes. Nodes are shared between cells and levels.

#include "libvdbappear/lightgrid/cell_interpolation.h"
#include "libvdbappear/lightgrid/sh_grid_lookup.h"
#include "libvdbappear/lightgrid/sh_lighting.h"

#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace vdbappear {

class ProgressBar;
class ZonalFactorisation;

struct AdaptiveGridOptions {
  int base_resolution = 4;   // nodes along the longest axis at level 0
  int max_level = 3;         // finest cells: base spacing / 2^max_level
  double tolerance = 0.05;   // relative to the largest |L_00| of the base nodes
  std::size_t max_nodes = 1u << 20;  // refinement stops before exceeding this
};

class AdaptiveShGrid final : public ShGridLookup {
 public:
  static AdaptiveShGrid build(const std::vector<PolygonLight>& lights, int lmax, const Vec3& lo, const Vec3& hi,
                              const AdaptiveGridOptions& options, ProgressBar* progress);
  // The grid a file holds: its nodes on the lattice (ShLattice; base nodes at multiples of
  // 2^levels). A cell is split where the node at its centre exists. Throws std::invalid_argument
  // when a cell lacks a corner.
  static AdaptiveShGrid fromNodes(int lmax, const ShLattice& lattice, std::vector<std::pair<LatticeIndex, ShLighting>> nodes);

  int lmax() const override { return lmax_; }
  std::size_t nodeCount() const override { return nodes_.size(); }
  std::size_t cellCount(int level) const;  // leaf and split cells at that level
  int levels() const { return int(cells_per_level_.size()); }

  bool contains(const Vec3& x) const override {
    return insideCellBox((x - origin_) / base_spacing_, Vec3(base_cells_[0], base_cells_[1], base_cells_[2]));
  }
  using ShGridLookup::interpolate;
  void interpolate(const Vec3& x, CellInterpolation method, std::vector<Vec3>& out) const override;
  ShLattice lattice() const override;
  void forEachNode(const std::function<void(const LatticeIndex&, const ShLighting&)>& visit) const override;

 private:
  struct Cell {
    int level, i, j, k;
  };
  static std::uint64_t key(int level, std::int64_t i, std::int64_t j, std::int64_t k);
  std::uint64_t nodeKey(int level, std::int64_t i, std::int64_t j, std::int64_t k) const;  // canonical: coarsest level
  double spacing(int level) const { return base_spacing_ / double(1 << level); }
  Vec3 nodePosition(int level, std::int64_t i, std::int64_t j, std::int64_t k) const;
  const ShLighting& corner(const Cell& c, int corner) const;
  bool hasCorners(const Cell& c) const;
  void indexCells();  // split_ and cells_per_level_ from the nodes (a split cell has its centre node)
  double errorEstimate(const Cell& c) const;
  void evaluateNodes(const std::vector<std::uint64_t>& keys, const std::vector<Vec3>& positions,
                     const std::vector<PolygonLight>& lights, const ZonalFactorisation& zh);

  int lmax_ = 0;
  Vec3 origin_ = Vec3::Zero();
  double base_spacing_ = 1;
  int base_cells_[3] = {1, 1, 1};
  std::vector<ShLighting> nodes_;
  std::unordered_map<std::uint64_t, std::uint32_t> node_index_;
  std::unordered_set<std::uint64_t> split_;  // cells that have children
  std::vector<std::size_t> cells_per_level_;
};

}  // namespace vdbappear
