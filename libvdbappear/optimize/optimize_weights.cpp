#include "libvdbappear/optimize/optimize_weights.h"

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_content_hash.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/util/system_memory.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

namespace vdbappear {

namespace {

void writeTextAtomically(const std::string& path, const std::string& text) {
  AtomicFile file(path);
  {
    std::ofstream out(file.temporaryPath(), std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw MediumError(fmt::format("{}: cannot be written", path));
  }
  file.commit();
}

nlohmann::json readCheckpoint(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MediumError(fmt::format("{}: no such checkpoint file", path));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw MediumError(fmt::format("{}: not a complete checkpoint (truncated or not JSON)", path));
  }
}

std::string logText(const WeightOptimizer& optimizer, const std::vector<std::string>& names) {
  std::string text;
  for (const IterationRecord& r : optimizer.history()) text += r.toJson(names).dump() + "\n";
  return text;
}

std::string statusOf(const WeightOptimizer& optimizer) {
  const IterationRecord& r = optimizer.history().back();
  double largest_step = 0;
  for (double s : r.step) largest_step = std::max(largest_step, s);
  return fmt::format("iteration {}/{}  E {:.4g}  step {:.3g}  change {:.2g}", r.t, optimizer.settings().max_iterations,
                     r.E, largest_step, r.relative_change);
}

// What addresses FULL in the reference cache and the checkpoints: its bytes, and the grid mapping it
// was read with, if any (a mapping makes another medium of the same file): the explicit rules and
// a preset's, detected or not.
// compact: the references are renders of FULL's compact form (half-float albedo and S), which differ
// from its float grids' within Monte Carlo error but not bit for bit.
std::string fullMediumKey(const std::string& path, const Medium& full, bool compact) {
  const std::string bytes = hashFile(path);
  if (full.grid_rules.empty() && !compact) return bytes;
  std::string key = bytes;
  for (const GridRule& rule : full.grid_rules) key += " --grid " + gridRuleText(rule);
  if (compact) key += " compact";
  return hashText(key);
}

// FULL as its references render it: the compact form, read in pieces where the file allows, else read
// whole and made compact; its float grids with full_precision or where the compact form does not hold it.
std::shared_ptr<const MediumView> fullView(const WeightOptimizationOptions& options, MediumPtr* full) {
  if (!options.full_precision) {
    std::string why_not;
    if (const auto compact = readCompactMedium(options.full, options.full_mapping, defaultMemoryBudget(), &why_not)) {
      *full = compact->medium;
      (*full)->read_notes = compact->notes;
      return std::make_shared<MediumView>(*compact, options.interpolation);
    }
  }
  *full = readMedium(options.full, options.full_mapping);
  if (!options.full_precision)
    if (const auto compact = compactMedium(*full, nullptr)) return std::make_shared<MediumView>(*compact, options.interpolation);
  return std::make_shared<MediumView>(*full, options.interpolation);
}

}  // namespace

WeightOptimizationResult optimizeWeights(const WeightOptimizationOptions& options,
                                         const std::function<void(const std::string&)>& note) {
  const Stopwatch total_clock;
  const SoloProcessGroup solo;
  const ProcessGroup& group = options.group ? *options.group : solo;
  const bool root = group.isRoot();
  // The inputs, read by every rank: a rank that cannot read them ends every rank here.
  MediumPtr full, lobes;
  std::shared_ptr<const MediumView> full_view;
  LobeMediumLayout layout;
  int factor = 0;
  std::string full_hash;
  group.together([&] {
    if (options.full == "-")
      throw MediumError("FULL must be a file, not stdin: its bytes address the cache of reference images");
    if (group.isShared() && options.lobes == "-")
      throw MediumError(fmt::format("LOBES on stdin reaches one rank of {}: give a file every rank can read", group.size()));
    full_view = fullView(options, &full);
    lobes = readMedium(options.lobes);
    layout = inspectLobeMedium(*lobes);
    factor = downsamplingFactor(*full, *lobes);
    full_hash = fullMediumKey(options.full, *full, full_view->compact());
  });
  if (root)
    for (const std::string& line : full->read_notes) note(line);

  OptimizerSettings settings = options.optimizer;
  settings.mode = options.mode.value_or(layout.coloured ? ColourMode::kColourScales : ColourMode::kGrey);
  const auto lobes_view = std::make_shared<MediumView>(lobes, options.interpolation);
  // Framed on the reduced medium's box, which holds the full one's (docs/medium.md §2): a training
  // ground at its bottom lies under both media.
  TrainingScenes scenes(lobes_view,
                        trainingSet(lobes_view->worldBounds(), options.resolution, options.training_lights, options.training_views),
                        &group);

  // References: from the cache, else rendered and stored.
  Stopwatch clock;
  const ReferenceCache cache(options.cache);
  std::vector<TrainingImage> images;
  {
    ProgressBar bar("references", scenes.size(), root && options.progress && stderrIsTerminal());
    images = prepareTrainingImages(full_view, full_hash, scenes, options.references, cache,
                                   [&](std::size_t) { bar.advance(); });
  }
  const double reference_seconds = clock.lap();
  WeightOptimizationResult result;
  result.references = int(images.size());
  for (const TrainingImage& image : images) result.cache_hits += image.cache_hit;
  if (cache.enabled() && root)
    note(fmt::format("references: {} of {} from the cache ({}), {} rendered in {:.1f} s", result.cache_hits,
                     result.references, cache.folder(), result.references - result.cache_hits, reference_seconds));

  const nlohmann::json inputs = {
      {"full", full_hash},
      {"lobes", mediumContentHash(*lobes)},
      {"training", {{"lights", options.training_lights}, {"views", options.training_views}, {"resolution", options.resolution},
                    {"reference_spp", options.references.reference_spp}, {"mask_spp", options.references.mask_spp}}},
      {"interp", interpolationName(options.interpolation)},
      {"settings", settings.iterateJson()}};
  WeightOptimizer optimizer(scenes, std::move(images), layout, settings);
  if (!options.resume.empty()) {
    group.together([&] {
      try {
        optimizer.resume(readCheckpoint(options.resume), inputs);
      } catch (const std::invalid_argument& e) {
        throw MediumError(fmt::format("{}: {}", options.resume, e.what()));
      }
    });
    if (root) note(fmt::format("resumed from {} after iteration {}", options.resume, optimizer.iteration()));
  }

  // SGD, with the log and the checkpoint rewritten after every iteration.
  const std::vector<std::string> names = optimizer.factors().parameterNames();
  ProgressBar bar("optimising", std::uint64_t(settings.max_iterations), root && options.progress && stderrIsTerminal());
  bar.advance(std::uint64_t(optimizer.iteration()));
  double optimize_seconds = 0;
  for (const IterationRecord& r : optimizer.history()) optimize_seconds += r.seconds;
  while (!optimizer.done()) {
    const IterationRecord& record = optimizer.iterate();
    optimize_seconds += record.seconds;
    if (root && !options.log.empty()) writeTextAtomically(options.log, logText(optimizer, names));
    if (root && !options.checkpoint.empty()) writeTextAtomically(options.checkpoint, optimizer.checkpoint(inputs).dump(1) + "\n");
    bar.setStatus(statusOf(optimizer));
    bar.advance();
  }
  bar.finish();
  clock.lap();
  const TrainingError final_error = optimizer.evaluate(optimizer.factors(), 0);
  const double final_seconds = clock.lap();

  const auto& history = optimizer.history();
  // Per training image and cluster, the relative error of each channel's restricted mean.
  const auto errorTable = [&](const std::vector<std::vector<Rgb>>& errors) {
    nlohmann::json table = nlohmann::json::object();
    for (std::size_t i = 0; i < errors.size() && i < optimizer.images().size(); ++i) {
      nlohmann::json clusters = nlohmann::json::array();
      for (const Rgb& e : errors[i]) clusters.push_back({e[0], e[1], e[2]});
      table[optimizer.images()[i].config.name()] = clusters;
    }
    return table;
  };
  result.record = {
      {"tool", "vdb_optimize_weights"},
      {"version", kVersion},
      {"factors", optimizer.factors().toJson()},
      {"parameters", names},
      {"E_naive", history.empty() ? 0.0 : history.front().E},
      {"E_final", final_error.E},
      {"E_final_per_image", final_error.per_image},
      {"relative_errors", {{"naive", history.empty() || history.front().t != 1 ? nlohmann::json() : errorTable(history.front().relative_errors)},
                           {"final", errorTable(final_error.relative_errors)}}},
      {"iterations", optimizer.iteration()},
      {"converged", optimizer.converged()},
      {"factor", factor},
      {"training", {{"lights", options.training_lights}, {"views", options.training_views},
                    {"resolution", options.resolution}, {"images", scenes.size()},
                    {"reference_spp", options.references.reference_spp}}},
      {"settings", settings.toJson()},
      {"interp", interpolationName(options.interpolation)},
      {"steps", optimizer.steps().toJson()},
      {"seconds", {{"references", reference_seconds},
                   {"optimisation", optimize_seconds},
                   {"final_evaluation", final_seconds},
                   {"total", total_clock.seconds()}}}};
  if (root) writeMedium(*applyWeightFactors(*lobes, optimizer.factors(), result.record), options.output, options.history_line);
  return result;
}

}  // namespace vdbappear
