#pragma once
// Naive downsampling of a medium file slab by slab (docs/scaling.md §5): the result of
// downsampleNaive(readMedium(path)), bit for bit, in memory bounded by a budget, whatever the
// medium's size. Light header: no OpenVDB.

#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_summary.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

class ProgressBar;

struct StreamedDownsample {
  DownsampleResult result;
  MediumSummary input;             // summed over the slabs
  MediumSummary output;            // summed over the coarse slabs, as they were in memory
  std::vector<std::string> notes;  // the reader's, as readMedium gives them
  int slabs = 0;
  std::uint64_t largest_slab_bytes = 0;  // the largest slab's grids in memory (OpenVDB's memUsage)
};

// Reads `path` in slabs along x of whole coarse leaves (8 F fine voxels), each as wide as fits in
// `memory_bytes` with the output, and downsamples each (downsampleNaive). nullopt, with the reason in
// `why_not`, where the file must be read whole: a grid mapping applies to it (--grid, or a preset
// that maps its grids), or it has grids of other value types. Throws MediumError as readMedium does
// (bad values name the first bad voxel slab by slab, along x), and naming the budget one slab needs
// when `memory_bytes` is too small for it. The coarse medium is validated slab by slab and holds its
// topology in memory, its values on scratch files in the folder of `output` ("-": the temporary
// folder; io/spilled_medium.h): writeMedium writes it a leaf at a time.
std::optional<StreamedDownsample> downsampleNaiveStreamed(const std::string& path, const GridMapping& mapping,
                                                          const DownsampleOptions& options, std::uint64_t memory_bytes,
                                                          std::string* why_not, ProgressBar* progress = nullptr,
                                                          const std::string& output = "-");

}  // namespace vdbappear
