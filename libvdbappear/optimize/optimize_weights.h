#pragma once
// The whole of vdb_optimize_weights as a library call: read FULL and LOBES, check that LOBES is
// vdb_lobe_cluster's output on FULL, prepare the training images (references from the cache),
// run the SGD of optimize/weight_optimizer.h with a JSON-lines log and an atomic checkpoint after
// every iteration, and write LOBES with optimised lobe weights and the metadata `weight_factors`.
// Light header.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/medium/interpolation.h"
#include "libvdbappear/optimize/training_images.h"
#include "libvdbappear/optimize/weight_optimizer.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>

namespace vdbappear {

class ProcessGroup;

struct WeightOptimizationOptions {
  std::string full, lobes, output;        // FULL (a file), LOBES and OUT (files, or "-")
  GridMapping full_mapping;               // how FULL's foreign grids are read (--grid, io/grid_mapping.h)
  std::optional<ColourMode> mode;         // none: colour scales if LOBES's weights are coloured, else grey
  OptimizerSettings optimizer;            // its mode is set from `mode`
  // The training set (optimize/training_set.h, docs/optimize.md §3): by default views from above
  // (+z and the four upper corners of the box) under the four band 0-1 skies over a ground; the
  // paper's set is training_views "faces", training_lights "sh1".
  std::string training_lights = "sh1+ground";
  std::string training_views = "+z,upper-corners";
  int resolution = 100;                   // training images: pixels on the long side
  TrainingRenderSettings references;
  Interpolation interpolation = Interpolation::kNearest;
  // FULL's renders (the references) from its float grids, read whole, instead of its compact form
  // read in pieces (medium/compact_medium.h, docs/rendering.md).
  bool full_precision = false;
  std::string cache;                      // reference cache folder; "" for none
  std::string log, checkpoint, resume;    // files; "" for none
  std::string history_line;               // appended to OUT's history
  bool progress = true;                   // progress bars on stderr (drawn only on a terminal)
  // The processes that share every render (cluster/process_group.h; null: this one alone). Each
  // calls optimizeWeights with the same options and follows the same trajectory; only the root
  // writes (OUT, the log, the checkpoint, the cache) and draws progress.
  const ProcessGroup* group = nullptr;
};

struct WeightOptimizationResult {
  nlohmann::json record;  // what OUT's `weight_factors` holds (factors, errors, settings, timings)
  int cache_hits = 0, references = 0;
};

// notes: one line at a time for the user (cache hits, resumption). Throws MediumError for bad input
// (naming the file and the grid) and std::invalid_argument for bad settings; in a group of several
// ranks, a bad input on any rank throws GroupFailure on all of them.
WeightOptimizationResult optimizeWeights(const WeightOptimizationOptions& options,
                                         const std::function<void(const std::string&)>& note);

}  // namespace vdbappear
