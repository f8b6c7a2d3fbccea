#include "libvdbappear/lobes/streamed_multi_lobe.h"

#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/scratch_parts.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/lobes/multi_lobe_stages.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>

#include <algorithm>

namespace vdbappear {

namespace {

std::string slabName(const openvdb::CoordBBox& piece, const std::string& path, const char* what) {
  return fmt::format("the {} slab {} of {}", what, pieceName(piece), path);
}

}  // namespace

std::optional<StreamedMultiLobe> downsampleMultiLobeStreamed(const std::string& path, const GridMapping& mapping,
                                                            const MultiLobeOptions& options, std::uint64_t memory_bytes,
                                                            std::string* why_not, ProgressBar* progress,
                                                            const std::string& output) {
  MultiLobeStages stages(options);  // checks the options
  MediumSlabs slabs(path, mapping);
  if (slabs.whyNotStreamed()) {
    if (why_not) *why_not = *slabs.whyNotStreamed();
    return std::nullopt;
  }
  const int band = 8 * options.factor;  // fine voxels per coarse leaf
  // The output's extra grids: four per lobe slot, and the cluster grid.
  const MediumSlabs::Plan plan = slabs.planWithin(band, memory_bytes, kSlabTargetBytes, 4 * stages.slotCount() + 1);
  StreamedMultiLobe out;
  out.notes = slabs.notes();
  out.slabs = int(plan.slabs.size());
  if (progress) progress->setTotal(2 * plan.slabs.size());  // fitted, ordered

  // Pass 1: each slab's coarse voxels and their lobes (§5), parked on disk; the albedos gathered.
  ScratchParts fitted(output);
  for (const openvdb::CoordBBox& range : plan.slabs) {
    MediumPtr part = slabs.slab(range);
    const MediumSummary part_summary = summarize(*part);
    addSummary(out.input, part_summary);
    out.largest_slab_bytes = std::max<std::uint64_t>(out.largest_slab_bytes, part_summary.memory_bytes);
    MediumPtr coarse = stages.coarsePart(*part);
    stages.fitPart(*part, *coarse);
    part.reset();  // the slab's leaves are freed here
    fitted.put(*coarse);
    if (progress) progress->advance(1);
  }
  slabs.finish();  // some voxel had density > 0
  out.parked_bytes = fitted.bytes();
  out.distinct_albedos = stages.distinctAlbedos();
  out.albedo_table_bytes = stages.tableBytes();

  // §6.2's clusters, and each one's reference voxel (Eq. 13) from a pass over the fitted slabs.
  stages.cluster();
  for (std::size_t i = 0; i < plan.slabs.size(); ++i)
    stages.pickReferences(*fitted.take(i, slabName(plan.slabs[i], path, "fitted")));

  // Pass 2: each slab's lobes ordered (Eq. 13) and weighed (Eq. 11), its values then on disk.
  SpilledMedium whole(output);
  for (std::size_t i = 0; i < plan.slabs.size(); ++i) {
    const std::string name = slabName(plan.slabs[i], path, "multi-lobe");
    MediumPtr coarse = fitted.take(i, name);
    stages.orderPart(*coarse);
    addSummary(out.output, summarize(*coarse));
    whole.add(*coarse, name);
    if (progress) progress->advance(1);
  }
  out.result = stages.result(whole.medium());
  out.result.medium->source = path;
  return out;
}

}  // namespace vdbappear
