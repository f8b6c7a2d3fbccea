#include "libvdbappear/downsample/coarse_transform.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

namespace vdbappear {

openvdb::math::Transform::Ptr coarseTransform(const openvdb::math::Transform& fine, int factor,
                                              const std::string& source) {
  if (!fine.isLinear())
    throw MediumError(fmt::format("{}: grid 'density': its transform ({}) is not linear; downsampling needs a "
                                  "linear transform", source, fine.mapType()));
  // index_fine = F * index_coarse + (F-1)/2, then the fine index-to-world map.
  auto coarse = fine.copy();
  coarse->preTranslate(openvdb::Vec3d(0.5 * (factor - 1)));
  coarse->preScale(double(factor));
  return coarse;
}

}  // namespace vdbappear
