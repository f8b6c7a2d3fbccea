#pragma once
// What reads SH lighting back from a grid (the uniform ShLightGrid or the AdaptiveShGrid): the RGB
// coefficients at any point, by interpolation within the cell that holds it.

#include "libvdbappear/lightgrid/cell_interpolation.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace vdbappear {

struct ShLighting;

// The lattice the nodes lie on, as files store it: node (a, b, c) of the finest lattice is at
// origin + spacing (a, b, c). `levels` is 0 for a uniform grid; an adaptive grid's base nodes are
// the multiples of 2^levels.
struct ShLattice {
  Vec3 origin = Vec3::Zero();
  double spacing = 1;
  int levels = 0;
};
using LatticeIndex = std::array<std::int64_t, 3>;

// Whether a point at `local` (in units of a cell, from the box's corner) lies in [0, upper] on every
// axis, to a relative 1e-9; false for non-finite points.
inline bool insideCellBox(const Vec3& local, const Vec3& upper) {
  const Vec3 slack = 1e-9 * (upper.array() + 1).matrix();
  return ((local + slack).array() >= 0).all() && ((local - slack).array() <= upper.array()).all();
}

class ShGridLookup {
 public:
  virtual ~ShGridLookup() = default;
  virtual int lmax() const = 0;
  virtual std::size_t nodeCount() const = 0;
  // Whether x lies in the grid's box (its outer nodes), to rounding; false for non-finite x.
  virtual bool contains(const Vec3& x) const = 0;
  // The RGB coefficients (index l (l + 1) + m) at x, clamped into the grid's box, into `out`;
  // zeros for non-finite x.
  virtual void interpolate(const Vec3& x, CellInterpolation method, std::vector<Vec3>& out) const = 0;
  virtual ShLattice lattice() const = 0;
  virtual void forEachNode(const std::function<void(const LatticeIndex&, const ShLighting&)>& visit) const = 0;
  std::vector<Vec3> interpolate(const Vec3& x, CellInterpolation method) const {
    std::vector<Vec3> out;
    interpolate(x, method, out);
    return out;
  }
};

}  // namespace vdbappear
