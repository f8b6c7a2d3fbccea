#pragma once
// Walks a ray through the majorant grid (medium/majorant_grid.h) as constant-majorant segments,
// hierarchically: OpenVDB's DDA steps over the children of each internal node, skips empty
// children and tiles in one step, and descends only into children that exist, down to the
// majorant voxels of a leaf (as math::VolumeHDDA does, but reporting each voxel's value).
// Internal header: includes OpenVDB.

#include <openvdb/math/DDA.h>
#include <openvdb/math/Ray.h>
#include <openvdb/openvdb.h>

#include <algorithm>

namespace vdbappear {

using MajorantRay = openvdb::math::Ray<double>;  // in majorant space, t = world distance

namespace majorant_detail {

// Level >= 0: DDA over the nodes of that level of the tree's node chain; -1: over voxels.
template <typename TreeT, int Level>
struct Walker {
  using NodeT = typename TreeT::RootNodeType::NodeChainType::template Get<Level>;

  template <typename AccessorT, typename Fn>
  static bool walk(const MajorantRay& ray, double t0, double t1, AccessorT& accessor, Fn& fn) {
    openvdb::math::DDA<MajorantRay, NodeT::TOTAL> dda(ray, t0, t1);
    do {
      const double a = dda.time(), b = std::min(dda.next(), t1);
      if (b > a) {
        if (accessor.template probeConstNode<NodeT>(dda.voxel())) {
          if (!Walker<TreeT, Level - 1>::walk(ray, a, b, accessor, fn)) return false;
        } else {
          const float value = accessor.getValue(dda.voxel());  // a tile, or empty space
          if (value > 0 && !fn(a, b, double(value))) return false;
        }
      }
    } while (dda.step());
    return true;
  }
};

template <typename TreeT>
struct Walker<TreeT, -1> {
  template <typename AccessorT, typename Fn>
  static bool walk(const MajorantRay& ray, double t0, double t1, AccessorT& accessor, Fn& fn) {
    openvdb::math::DDA<MajorantRay, 0> dda(ray, t0, t1);
    do {
      const double a = dda.time(), b = std::min(dda.next(), t1);
      const float value = accessor.getValue(dda.voxel());
      if (b > a && value > 0 && !fn(a, b, double(value))) return false;
    } while (dda.step());
    return true;
  }
};

}  // namespace majorant_detail

// Calls fn(t0, t1, sigma_maj) for each non-empty segment of the ray within [ray.t0(), ray.t1()],
// in order of t; stops early when fn returns false (and then returns false).
template <typename AccessorT, typename Fn>
bool forEachMajorantSegment(const MajorantRay& ray, AccessorT& accessor, Fn&& fn) {
  using TreeT = typename AccessorT::TreeType;
  constexpr int kTopLevel = int(TreeT::RootNodeType::ChildNodeType::LEVEL);
  if (!(ray.t1() > ray.t0())) return true;
  return majorant_detail::Walker<std::remove_const_t<TreeT>, kTopLevel>::walk(ray, ray.t0(), ray.t1(), accessor, fn);
}

}  // namespace vdbappear
