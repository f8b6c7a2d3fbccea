#include "libvdbappear/modularity/instance_mapping.h"

#include "libvdbappear/modularity/exemplar_set.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

namespace vdbappear {

using openvdb::Coord;

namespace {

bool isInstanced(const Medium& medium) {
  const auto kind = medium.metadata.getMetadata<openvdb::StringMetadata>(metadata_names::kExemplarKind);
  return kind && kind->value() == "instanced";
}

// Per exemplar, the box of its active density voxels within its block (empty if it has none).
std::vector<openvdb::CoordBBox> exemplarBoxes(const openvdb::FloatGrid& density, const Coord& block, int count) {
  std::vector<openvdb::CoordBBox> boxes(static_cast<std::size_t>(count));
  const auto add = [&](const Coord& ijk) {
    const Coord b = blockOf(ijk, block);
    if (b.x() < 0 || b.x() >= count || b.y() != 0 || b.z() != 0) return;  // not read through any layout
    boxes[std::size_t(b.x())].expand(ijk.offsetBy(-b.x() * block.x(), 0, 0));
  };
  for (auto v = density.cbeginValueOn(); v; ++v) {
    if (v.isVoxelValue()) {
      add(v.getCoord());
    } else {
      openvdb::CoordBBox box;
      v.getBoundingBox(box);
      for (const Coord& ijk : box) add(ijk);
    }
  }
  return boxes;
}

}  // namespace

std::optional<InstanceMapping> InstanceMapping::of(const Medium& medium, int block_multiple) {
  if (!isInstanced(medium)) return std::nullopt;
  const ExemplarSet set = readExemplarSet(medium, ExemplarKind::Instanced);
  for (int a = 0; a < 3; ++a)
    if (set.block[a] % block_multiple != 0)
      throw MediumError(fmt::format("{}: an instanced model needs block sides that are multiples of {} (these are "
                                    "{}x{}x{}): assemble it without --instanced", medium.source, block_multiple,
                                    set.block.x(), set.block.y(), set.block.z()));
  InstanceMapping mapping;
  mapping.block_ = set.block;
  mapping.count_ = set.count;
  mapping.layout_ = layoutOfMedium(medium);
  checkLayoutIds(mapping.layout_, set.count, medium.source);
  return mapping;
}

openvdb::CoordBBox InstanceMapping::modelBounds(const openvdb::FloatGrid& density) const {
  const std::vector<openvdb::CoordBBox> boxes = exemplarBoxes(density, block_, count_);
  openvdb::CoordBBox model;
  for (int k = 0; k < layout_.depth; ++k)
    for (int j = 0; j < layout_.height; ++j)
      for (int i = 0; i < layout_.width; ++i) {
        const int e = layout_.at(i, j, k);
        if (e == ExemplarLayout::kEmpty || boxes[std::size_t(e)].empty()) continue;
        openvdb::CoordBBox box = boxes[std::size_t(e)];
        box.translate(Coord(i * block_.x(), j * block_.y(), k * block_.z()));
        model.expand(box);
      }
  return model;
}

std::uint64_t InstanceMapping::modelMajorantVoxelCount(const openvdb::FloatGrid& set_majorant, int unit) const {
  return placedTotal(activeVoxelsPerBlock(set_majorant, Coord(block_.x() / unit, block_.y() / unit, block_.z() / unit)));
}

std::uint64_t InstanceMapping::modelVoxelCount(const openvdb::FloatGrid& density) const {
  return placedTotal(activeVoxelsPerBlock(density, block_));
}

std::uint64_t InstanceMapping::placedTotal(std::map<Coord, std::uint64_t> per_exemplar) const {
  std::uint64_t total = 0;
  for (int e : layout_.ids)
    if (e != ExemplarLayout::kEmpty) total += per_exemplar[Coord(e, 0, 0)];
  return total;
}

}  // namespace vdbappear
