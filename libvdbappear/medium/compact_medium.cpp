#include "libvdbappear/medium/compact_medium.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/medium/compact_attributes.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace vdbappear {

namespace {

// The grids a render reads that the compact form does not hold (docs/medium.md §3-§7).
bool isRenderedOtherGrid(const std::string& name) {
  return isLobeGridName(name) || isBlockIndexedGridName(name) || name == grid_names::kPhaseTable ||
         name == grid_names::kPhaseId || name == grid_names::kCluster || name == grid_names::kEmission ||
         name == grid_names::kBlackbodyTemperature;
}

// The medium without its albedo and SGGX grids (they are in the records) and without the grids no
// render reads; the density shared.
MediumPtr densityOnly(const Medium& medium) {
  auto shell = std::make_shared<Medium>();
  shell->density = medium.density;
  shell->metadata = medium.metadata;
  shell->source = medium.source;
  shell->grid_rules = medium.grid_rules;
  shell->read_notes = medium.read_notes;
  return shell;
}

bool needsRecords(const Medium& medium) { return medium.albedo || medium.hasSggx(); }

}  // namespace

std::optional<std::string> whyNotCompact(const Medium& medium) {
  if (medium.hg_g) return std::string("it has an hg_g grid, which the compact form does not hold");
  std::vector<std::string> held_elsewhere;  // sorted: the whole read and a slab list grids in different orders
  for (const auto& grid : medium.other_grids)
    if (isRenderedOtherGrid(grid->getName())) held_elsewhere.push_back("'" + grid->getName() + "'");
  std::sort(held_elsewhere.begin(), held_elsewhere.end());
  if (!held_elsewhere.empty())
    return fmt::format("it has grids the compact form does not hold: {}", fmt::join(held_elsewhere, ", "));
  if (medium.metadata[metadata_names::kExemplarKind])
    return std::string("it is an instanced model (exemplar_kind), which renders from its grids");
  if (medium.density->tree().activeTileCount() > 0)
    return std::string("its density has active tiles, which the compact form does not hold");
  return std::nullopt;
}

std::optional<CompactMedium> compactMedium(const MediumPtr& medium, std::string* why_not) {
  if (const auto why = whyNotCompact(*medium)) {
    if (why_not) *why_not = *why;
    return std::nullopt;
  }
  CompactMedium out;
  out.medium = densityOnly(*medium);
  out.notes = medium->read_notes;
  if (needsRecords(*medium)) {
    auto attributes = std::make_shared<CompactAttributes>();
    attributes->add(*medium);
    out.attribute_bytes = attributes->memoryBytes();
    out.attributes = std::move(attributes);
  }
  out.density_bytes = out.medium->density->memUsage();
  return out;
}

std::optional<CompactMedium> readCompactMedium(const std::string& path, const GridMapping& mapping,
                                               std::uint64_t memory_bytes, std::string* why_not, ProgressBar* progress) {
  MediumSlabs slabs(path, mapping);
  const auto give_up = [&](const std::string& why) {
    if (why_not) *why_not = why;
    return std::nullopt;
  };
  if (slabs.whyNotStreamed()) return give_up(*slabs.whyNotStreamed());
  // Pieces of whole leaves (a band of 8 voxels); nothing of the output stays but what is rendered.
  const MediumSlabs::Plan plan = slabs.planWithin(8, memory_bytes, kSlabTargetBytes);
  if (progress) progress->setTotal(plan.slabs.size());
  CompactMedium out;
  out.notes = slabs.notes();
  out.pieces = int(plan.slabs.size());
  auto attributes = std::make_shared<CompactAttributes>();
  bool records = false;  // every piece has the file's grids
  for (const openvdb::CoordBBox& range : plan.slabs) {
    const MediumPtr piece = slabs.slab(range);
    if (const auto why = whyNotCompact(*piece)) return give_up(*why);
    if (!out.medium) {
      out.medium = densityOnly(*piece);
      out.medium->density = piece->density->copyWithNewTree();
      records = needsRecords(*piece);
    }
    if (records) attributes->add(*piece);
    // The piece's leaves join the whole, masks unchanged (pieces share no leaf).
    out.medium->density->tree().merge(piece->density->tree(), openvdb::MERGE_NODES);
    if (progress) progress->advance(1);
  }
  slabs.finish();  // some voxel had density > 0
  out.medium->source = path;
  if (records) {
    out.attribute_bytes = attributes->memoryBytes();
    out.attributes = std::move(attributes);
  }
  out.density_bytes = out.medium->density->memUsage();
  return out;
}

}  // namespace vdbappear
