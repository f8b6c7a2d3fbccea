#include "libvdbappear/modularity/exemplar_set.h"

#include "libvdbappear/io/medium_content_hash.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cmath>

namespace vdbappear {

namespace {

ExemplarKind kindFrom(const Medium& medium) {
  const auto kind = medium.metadata.getMetadata<openvdb::StringMetadata>(metadata_names::kExemplarKind);
  if (!kind || kind->value() == "blocks") return ExemplarKind::Blocks;
  if (kind->value() == "stacked") return ExemplarKind::Stacked;
  if (kind->value() == "model") return ExemplarKind::Model;
  if (kind->value() == "instanced") return ExemplarKind::Instanced;
  throw MediumError(fmt::format("{}: metadata '{}' = '{}': expected blocks, stacked, model or instanced", medium.source,
                                metadata_names::kExemplarKind, kind->value()));
}

const char* whatToGive(ExemplarKind kind) {
  switch (kind) {
    case ExemplarKind::Blocks: return "a block set (vdb_make_medium exemplars, or vdb_exemplar_stack split)";
    case ExemplarKind::Stacked: return "the output of vdb_exemplar_stack stack, or of the pipeline run on it";
    case ExemplarKind::Model: return "an assembled model";
    case ExemplarKind::Instanced: return "an instanced model (vdb_exemplar_stack assemble --instanced)";
  }
  return "";
}

// The medium's voxel size over the blocks' original one: an integer F >= 1 on every axis.
int reductionFactor(const Medium& medium) {
  const openvdb::Vec3d here = medium.transform().voxelSize();
  const auto original = medium.metadata.getMetadata<openvdb::Vec3DMetadata>(metadata_names::kExemplarVoxelSize);
  if (!original) return 1;
  const double F = std::round(here.x() / original->value().x());
  for (int a = 0; a < 3; ++a)
    if (!(F >= 1 && std::abs(here[a] / original->value()[a] - F) <= 1e-6 * F))
      throw MediumError(fmt::format("{}: metadata '{}' = ({}, {}, {}): the medium's voxel size ({}, {}, {}) is not an "
                                    "integer multiple of it", medium.source, metadata_names::kExemplarVoxelSize,
                                    original->value().x(), original->value().y(), original->value().z(), here.x(),
                                    here.y(), here.z()));
  return int(F);
}

}  // namespace

const char* exemplarKindName(ExemplarKind kind) {
  switch (kind) {
    case ExemplarKind::Blocks: return "blocks";
    case ExemplarKind::Stacked: return "stacked";
    case ExemplarKind::Model: return "model";
    case ExemplarKind::Instanced: return "instanced";
  }
  return "";
}

ExemplarSet readExemplarSet(const Medium& medium, ExemplarKind expected) {
  const auto count = medium.metadata.getMetadata<openvdb::Int32Metadata>(metadata_names::kExemplarCount);
  const auto block = medium.metadata.getMetadata<openvdb::Vec3IMetadata>(metadata_names::kExemplarBlock);
  if (!count || !block || count->value() < 1 || block->value().x() < 1 || block->value().y() < 1 ||
      block->value().z() < 1)
    throw MediumError(fmt::format("{}: no metadata 'exemplar_count' (int >= 1) and 'exemplar_block' (vec3i >= 1): not "
                                  "made of exemplar blocks; give {}", medium.source, whatToGive(expected)));
  ExemplarSet set;
  set.count = count->value();
  set.kind = kindFrom(medium);
  if (set.kind != expected)
    throw MediumError(fmt::format("{}: metadata 'exemplar_kind' is {}: give {}", medium.source,
                                  exemplarKindName(set.kind), whatToGive(expected)));
  set.factor = reductionFactor(medium);
  const openvdb::Vec3i original = block->value();
  for (int a = 0; a < 3; ++a)
    if (original[a] % set.factor != 0)
      throw MediumError(fmt::format("{}: blocks of {}x{}x{} voxels were reduced by a factor {}, which does not divide "
                                    "their side {}: blocks no longer hold whole voxels (downsample by a divisor of "
                                    "the block side)", medium.source, original.x(), original.y(), original.z(),
                                    set.factor, original[a]));
  set.block = openvdb::Coord(original.x() / set.factor, original.y() / set.factor, original.z() / set.factor);
  if (const auto name = medium.metadata.getMetadata<openvdb::StringMetadata>(metadata_names::kExemplarSet))
    set.name = name->value();
  return set;
}

void writeExemplarSet(Medium& medium, const ExemplarSet& set) {
  auto& meta = medium.metadata;
  for (const char* key : {metadata_names::kExemplarCount, metadata_names::kExemplarBlock,
                          metadata_names::kExemplarVoxelSize, metadata_names::kExemplarKind,
                          metadata_names::kExemplarSet})
    meta.removeMeta(key);
  meta.insertMeta(metadata_names::kExemplarCount, openvdb::Int32Metadata(set.count));
  meta.insertMeta(metadata_names::kExemplarBlock,
                  openvdb::Vec3IMetadata(openvdb::Vec3i(set.block.x(), set.block.y(), set.block.z())));
  meta.insertMeta(metadata_names::kExemplarKind, openvdb::StringMetadata(exemplarKindName(set.kind)));
  if (!set.name.empty()) meta.insertMeta(metadata_names::kExemplarSet, openvdb::StringMetadata(set.name));
}

std::string exemplarSetName(const Medium& blocks) {
  return fmt::format("xxh3:{} {}", mediumContentHash(blocks), blocks.source);
}

}  // namespace vdbappear
