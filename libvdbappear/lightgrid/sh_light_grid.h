#pragma once
// SH lighting coefficients and gradients on a uniform grid of nodes, read back anywhere inside by
// interpolation within the cell (Algorithm 1 of dissertation ch. 5). The interpolation costs the
// same whatever the number of lights.

#include "libvdbappear/lightgrid/cell_interpolation.h"
#include "libvdbappear/lightgrid/sh_grid_lookup.h"
#include "libvdbappear/lightgrid/sh_lighting.h"

#include <Eigen/Core>

#include <vector>

namespace vdbappear {

class ProgressBar;
class ZonalFactorisation;

struct ShGridLayout {
  Vec3 origin = Vec3::Zero();                  // world position of node (0, 0, 0)
  double spacing = 1;                          // cubic cells
  Eigen::Vector3i nodes = Eigen::Vector3i(2, 2, 2);

  // The layout covering [lo, hi] with `resolution` nodes along its longest axis (>= 2), and as
  // many along the others as cover them at the same spacing.
  static ShGridLayout covering(const Vec3& lo, const Vec3& hi, int resolution);
  static ShGridLayout withSpacing(const Vec3& lo, const Vec3& hi, double spacing);
  Vec3 position(int i, int j, int k) const { return origin + spacing * Vec3(i, j, k); }
  std::size_t count() const { return std::size_t(nodes.x()) * nodes.y() * nodes.z(); }
};

class ShLightGrid final : public ShGridLookup {
 public:
  ShLightGrid(int lmax, const ShGridLayout& layout);

  // Evaluates every node analytically (in parallel); progress may be null.
  static ShLightGrid evaluate(const std::vector<PolygonLight>& lights, int lmax, const ShGridLayout& layout,
                              ProgressBar* progress);
  static ShLightGrid evaluate(const std::vector<PolygonLight>& lights, const ZonalFactorisation& zh,
                              const ShGridLayout& layout, ProgressBar* progress);

  int lmax() const override { return lmax_; }
  std::size_t nodeCount() const override { return nodes_.size(); }
  const ShGridLayout& layout() const { return layout_; }
  ShLighting& node(int i, int j, int k) { return nodes_[index(i, j, k)]; }
  const ShLighting& node(int i, int j, int k) const { return nodes_[index(i, j, k)]; }

  bool contains(const Vec3& x) const override {
    return insideCellBox((x - layout_.origin) / layout_.spacing, (layout_.nodes.array() - 1).cast<double>().matrix());
  }
  using ShGridLookup::interpolate;
  void interpolate(const Vec3& x, CellInterpolation method, std::vector<Vec3>& out) const override;
  ShLattice lattice() const override { return {layout_.origin, layout_.spacing, 0}; }
  void forEachNode(const std::function<void(const LatticeIndex&, const ShLighting&)>& visit) const override;

 private:
  std::size_t index(int i, int j, int k) const { return (std::size_t(k) * layout_.nodes.y() + j) * layout_.nodes.x() + i; }

  int lmax_;
  ShGridLayout layout_;
  std::vector<ShLighting> nodes_;
};

}  // namespace vdbappear
