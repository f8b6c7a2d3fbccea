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

// The level a walk can start from: below the top while the grid's active voxels lie within one
// existing node of the level above, so that a ray clipped to their box crosses that one node there
// and the walk of that level would only hand its whole span down. A medium of up to 8^3 majorant
// voxels in one leaf walks its voxels directly; up to 128^3 in one internal node, its leaves.
template <typename TreeT, int Level>
int walkStartLevel(const TreeT& tree, const openvdb::CoordBBox& box) {
  if constexpr (Level < 0) {
    return -1;
  } else {
    using NodeT = typename TreeT::RootNodeType::NodeChainType::template Get<Level>;
    const openvdb::Coord &a = box.min(), &b = box.max();
    const int n = int(NodeT::TOTAL);
    const bool one_node = (a.x() >> n) == (b.x() >> n) && (a.y() >> n) == (b.y() >> n) && (a.z() >> n) == (b.z() >> n);
    if (box.empty() || !one_node || !tree.template probeConstNode<NodeT>(a)) return Level;
    return walkStartLevel<TreeT, Level - 1>(tree, box);
  }
}

template <typename TreeT, int Level, typename AccessorT, typename Fn>
bool walkFrom(int start_level, const MajorantRay& ray, AccessorT& accessor, Fn& fn) {
  if constexpr (Level >= 0) {
    if (start_level < Level) return walkFrom<TreeT, Level - 1>(start_level, ray, accessor, fn);
  }
  return Walker<TreeT, Level>::walk(ray, ray.t0(), ray.t1(), accessor, fn);
}

}  // namespace majorant_detail

// The level forEachMajorantSegment can start from for rays clipped to `active_box`, the box of
// the majorant grid's active voxels.
template <typename TreeT>
int majorantWalkStartLevel(const TreeT& tree, const openvdb::CoordBBox& active_box) {
  constexpr int kTopLevel = int(TreeT::RootNodeType::ChildNodeType::LEVEL);
  return majorant_detail::walkStartLevel<TreeT, kTopLevel>(tree, active_box);
}

// Calls fn(t0, t1, sigma_maj) for each non-empty segment of the ray within [ray.t0(), ray.t1()],
// in order of t; stops early when fn returns false (and then returns false). A ray clipped to the
// grid's active box may start from majorantWalkStartLevel: the same segments (an end at the box may
// differ in rounding), from fewer DDAs.
template <typename AccessorT, typename Fn>
bool forEachMajorantSegment(const MajorantRay& ray, AccessorT& accessor, Fn&& fn,
                            int start_level = int(AccessorT::TreeType::RootNodeType::ChildNodeType::LEVEL)) {
  using TreeT = std::remove_const_t<typename AccessorT::TreeType>;
  constexpr int kTopLevel = int(TreeT::RootNodeType::ChildNodeType::LEVEL);
  if (!(ray.t1() > ray.t0())) return true;
  return majorant_detail::walkFrom<TreeT, kTopLevel>(start_level, ray, accessor, fn);
}

}  // namespace vdbappear
