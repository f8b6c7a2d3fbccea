#pragma once
// The majorant of an instanced model (docs/modularity.md) walked without building it: a DDA over the
// layout's blocks and, inside each placed block, the hierarchical walk of medium/majorant_traversal.h
// over its exemplar's majorant in the block set's majorant grid, the ray shifted to where that
// exemplar lies in the set. Memory: the block set's majorant and the layout; nothing per model voxel.
// Internal header: includes OpenVDB.

#include "libvdbappear/medium/majorant_traversal.h"
#include "libvdbappear/modularity/instance_mapping.h"

namespace vdbappear {

// As forEachMajorantSegment, for a ray in the model's majorant space (majorant voxels of `unit`^3
// model voxels; block sides are multiples of `unit`, InstanceMapping::of). set_majorant: an accessor
// of the block set's majorant grid.
template <typename AccessorT, typename Fn>
bool forEachInstancedMajorantSegment(const MajorantRay& ray, const InstanceMapping& instances, int unit,
                                     AccessorT& set_majorant, Fn&& fn) {
  using TreeT = std::remove_const_t<typename AccessorT::TreeType>;
  constexpr int kTopLevel = int(TreeT::RootNodeType::ChildNodeType::LEVEL);
  const ExemplarLayout& layout = instances.layout();
  const openvdb::Vec3d block(instances.block().x() / unit, instances.block().y() / unit, instances.block().z() / unit);
  // Block space: block (i, j, k) of the layout is the unit cube [i, i+1) x [j, j+1) x [k, k+1); t unchanged.
  MajorantRay blocks(ray.eye() / block, ray.dir() / block, ray.t0(), ray.t1());
  if (!blocks.clip(openvdb::math::BBox<openvdb::Vec3d>(openvdb::Vec3d(0.0),
                                                       openvdb::Vec3d(layout.width, layout.height, layout.depth))))
    return true;
  openvdb::math::DDA<MajorantRay, 0> dda(blocks, blocks.t0(), blocks.t1());
  do {
    const double a = dda.time(), b = std::min(dda.next(), blocks.t1());
    const openvdb::Coord& ijk = dda.voxel();
    if (b > a && ijk.x() >= 0 && ijk.y() >= 0 && ijk.z() >= 0 && ijk.x() < layout.width && ijk.y() < layout.height &&
        ijk.z() < layout.depth) {
      const int e = layout.at(ijk.x(), ijk.y(), ijk.z());
      if (e != ExemplarLayout::kEmpty) {
        // Model block (i, j, k) reads exemplar e, which lies at block (e, 0, 0) of the set.
        const openvdb::Vec3d shift((e - ijk.x()) * block.x(), -ijk.y() * block.y(), -ijk.z() * block.z());
        const MajorantRay in_set(ray.eye() + shift, ray.dir(), a, b);
        if (!majorant_detail::Walker<TreeT, kTopLevel>::walk(in_set, a, b, set_majorant, fn)) return false;
      }
    }
  } while (dda.step());
  return true;
}

}  // namespace vdbappear
