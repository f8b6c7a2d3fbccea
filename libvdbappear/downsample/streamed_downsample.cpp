#include "libvdbappear/downsample/streamed_downsample.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>

#include <algorithm>

namespace vdbappear {

std::optional<StreamedDownsample> downsampleNaiveStreamed(const std::string& path, const GridMapping& mapping,
                                                          const DownsampleOptions& options, std::uint64_t memory_bytes,
                                                          std::string* why_not, ProgressBar* progress,
                                                          const std::string& output) {
  if (options.factor < 2 || options.factor > kMaxDownsampleFactor)
    throw std::invalid_argument(fmt::format("downsampling factor {} outside 2..{}", options.factor, kMaxDownsampleFactor));
  MediumSlabs slabs(path, mapping);
  if (slabs.whyNotStreamed()) {
    if (why_not) *why_not = *slabs.whyNotStreamed();
    return std::nullopt;
  }
  const int band = 8 * options.factor;  // fine voxels per coarse leaf
  const MediumSlabs::Plan plan = slabs.planWithin(band, memory_bytes, kSlabTargetBytes);
  StreamedDownsample out;
  out.notes = slabs.notes();
  out.slabs = int(plan.slabs.size());
  if (progress) progress->setTotal(plan.slabs.size());
  SpilledMedium whole(output);  // the coarse slabs, their values on disk until written
  for (const openvdb::CoordBBox& range : plan.slabs) {
    MediumPtr part = slabs.slab(range);
    const MediumSummary part_summary = summarize(*part);
    addSummary(out.input, part_summary);
    out.largest_slab_bytes = std::max<std::uint64_t>(out.largest_slab_bytes, part_summary.memory_bytes);
    DownsampleResult coarse = downsampleNaive(*part, options);
    part.reset();  // the slab's leaves are freed here
    for (const auto& warning : coarse.warnings)
      if (std::find(out.result.warnings.begin(), out.result.warnings.end(), warning) == out.result.warnings.end())
        out.result.warnings.push_back(warning);
    addSummary(out.output, summarize(*coarse.medium));
    whole.add(*coarse.medium, fmt::format("the downsampled slab {} of {}", pieceName(range), path));
    if (progress) progress->advance(1);
  }
  slabs.finish();  // some voxel had density > 0
  out.result.medium = whole.medium();
  out.result.medium->source = path;
  return out;
}

}  // namespace vdbappear
