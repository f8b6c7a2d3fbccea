#include "libvdbappear/downsample/streamed_downsample.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <unistd.h>

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

// Moves the leaves of `part`'s grids into `whole`'s: the slabs' coarse leaves are disjoint (a slab
// is whole coarse leaves), so the merged trees are those one downsampling of the whole would build.
template <typename GridPtr>
void mergeGrid(const GridPtr& whole, const GridPtr& part) {
  if (whole && part) whole->tree().merge(part->tree());
}

void mergeInto(Medium& whole, Medium& part) {
  mergeGrid(whole.density, part.density);
  mergeGrid(whole.albedo, part.albedo);
  mergeGrid(whole.sggx_diag, part.sggx_diag);
  mergeGrid(whole.sggx_offdiag, part.sggx_offdiag);
  mergeGrid(whole.hg_g, part.hg_g);
  for (const auto& grid : whole.other_grids) {
    const auto other = std::find_if(part.other_grids.begin(), part.other_grids.end(),
                                    [&](const auto& g) { return g->getName() == grid->getName(); });
    if (other == part.other_grids.end() || isBlockIndexedGridName(grid->getName()) ||
        grid->getName() == grid_names::kPhaseTable)
      continue;  // not indexed by voxel: every slab carries the same copy
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)) mergeGrid(f, openvdb::gridPtrCast<openvdb::FloatGrid>(*other));
    else if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid)) mergeGrid(v, openvdb::gridPtrCast<openvdb::Vec3SGrid>(*other));
    else throw MediumError(fmt::format("{}: grid '{}': a downsampled grid of {} values cannot be merged", whole.source,
                                       grid->getName(), grid->valueType()));
  }
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

std::uint64_t defaultMemoryBudget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const std::uint64_t machine = pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : std::uint64_t(16e9);
  return std::min<std::uint64_t>(machine / 4, std::uint64_t(4 * kGB));
}

std::optional<StreamedDownsample> downsampleNaiveStreamed(const std::string& path, const GridMapping& mapping,
                                                          const DownsampleOptions& options, std::uint64_t memory_bytes,
                                                          std::string* why_not, ProgressBar* progress) {
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
  std::uint64_t largest = 0;
  for (const SlabRange& range : plan.slabs) {
    MediumPtr part = slabs.slab(range);
    const MediumSummary part_summary = summarize(*part);
    addSummary(out.input, part_summary);
    largest = std::max<std::uint64_t>(largest, part_summary.memory_bytes);
    DownsampleResult coarse = downsampleNaive(*part, options);
    part.reset();  // the slab's leaves are freed here
    for (const auto& warning : coarse.warnings)
      if (std::find(out.result.warnings.begin(), out.result.warnings.end(), warning) == out.result.warnings.end())
        out.result.warnings.push_back(warning);
    if (!out.result.medium) out.result.medium = coarse.medium;
    else mergeInto(*out.result.medium, *coarse.medium);
    if (progress) progress->advance(1);
  }
  slabs.finish();  // some voxel had density > 0
  out.result.medium->source = path;
  out.largest_slab_bytes = largest;
  return out;
}

}  // namespace vdbappear
