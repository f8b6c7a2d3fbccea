#pragma once
// vdb_lobe_cluster's reduction of a medium file slab by slab (docs/scaling.md §5): the result of
// downsampleMultiLobe(readMedium(path)), bit for bit, in memory bounded by a budget, whatever the
// medium's size. Two passes: each slab is fitted (lobes/multi_lobe_stages.h) and parked on disk; once
// every slab has given its albedos, the clusters are made, and each parked slab is read back, ordered
// and weighed, and handed to the output, whose values wait on disk until written. Light header: no
// OpenVDB.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

class ProgressBar;

struct StreamedMultiLobe {
  MultiLobeResult result;
  MediumSummary input;             // summed over the slabs
  MediumSummary output;            // summed over the ordered coarse slabs, as they were in memory
  std::vector<std::string> notes;  // the reader's, as readMedium gives them
  int slabs = 0;
  std::uint64_t largest_slab_bytes = 0;  // the largest slab's grids in memory (OpenVDB's memUsage)
  std::uint64_t parked_bytes = 0;        // the fitted slabs on disk between the passes
  std::size_t distinct_albedos = 0;      // the clustering's input, gathered over the slabs
  std::uint64_t albedo_table_bytes = 0;  // its memory, held from the first slab to the end
};

// As downsampleNaiveStreamed (downsample/streamed_downsample.h): nullopt, with the reason in
// `why_not`, where the file must be read whole; MediumError as downsampleMultiLobe and readMedium
// throw, and naming the budget one slab needs when `memory_bytes` is too small for it; scratch files
// in the folder of `output` ("-": the temporary folder), removed as they are made.
std::optional<StreamedMultiLobe> downsampleMultiLobeStreamed(const std::string& path, const GridMapping& mapping,
                                                            const MultiLobeOptions& options, std::uint64_t memory_bytes,
                                                            std::string* why_not, ProgressBar* progress = nullptr,
                                                            const std::string& output = "-");

}  // namespace vdbappear
