#include "libvdbappear/downsample/streamed_downsample.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace vdbappear {

namespace {

constexpr double kGB = 1e9;
// Slabs of at most this much where the budget allows more: smaller slabs cost no time (a 512^3
// twill: 4.0 s in 6 slabs of 0.49 GB, 4.4 s in 32 of 0.1 GB, 5.3 s in one of 2.7 GB).
constexpr std::uint64_t kSlabTargetBytes = std::uint64_t(0.5 * kGB);

// x rounded up to three significant digits: a budget that is enough.
double roundedUp(double x) {
  const double step = std::pow(10.0, std::floor(std::log10(x)) - 2);
  return std::ceil(x / step) * step;
}

void addSummary(MediumSummary& total, const MediumSummary& part) {
  total.active_voxels += part.active_voxels;
  total.memory_bytes += part.memory_bytes;
  total.voxel_size = part.voxel_size;
  for (const GridSummary& g : part.grids) {
    auto it = std::find_if(total.grids.begin(), total.grids.end(), [&](const GridSummary& t) { return t.name == g.name; });
    if (it == total.grids.end()) {
      total.grids.push_back(g);
    } else {
      it->active_voxels += g.active_voxels;
      it->memory_bytes += g.memory_bytes;
    }
  }
}

}  // namespace

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
  const MediumSlabs::Plan plan = slabs.plan(band, memory_bytes, kSlabTargetBytes);
  if (plan.slabs.empty() && plan.largest_band_bytes > 0)
    throw MediumError(fmt::format("{}: a memory budget of {:.3g} GB is too small: one slab of {} voxels along x needs "
                                  "{:.3g} GB with what stays in memory (--memory {:.3g} or more)",
                                  path, memory_bytes / kGB, band, (plan.resident_bytes + plan.largest_band_bytes) / kGB,
                                  roundedUp((plan.resident_bytes + plan.largest_band_bytes) / kGB)));
  StreamedDownsample out;
  out.notes = slabs.notes();
  out.slabs = int(plan.slabs.size());
  if (progress) progress->setTotal(plan.slabs.size());
  SpilledMedium whole(output);  // the coarse slabs, their values on disk until written
  for (const SlabRange& range : plan.slabs) {
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
    whole.add(*coarse.medium, fmt::format("the downsampled slab x = {}..{} of {}", range.first, range.second - 1, path));
    if (progress) progress->advance(1);
  }
  slabs.finish();  // some voxel had density > 0
  out.result.medium = whole.medium();
  out.result.medium->source = path;
  return out;
}

}  // namespace vdbappear
