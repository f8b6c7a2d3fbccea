// vdb_optimize_weights: lobe-weight factors by stochastic gradient descent on path-traced gradient
// images (§6.3-6.4 and Appendix A of Zhao et al. 2016, "Downsampling Scattering Parameters for
// Rendering Anisotropic Media").
#include "tool_main.h"

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/optimize/optimize_weights.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_optimize_weights";

constexpr const char* kExamples = R"(Examples:
  vdb_lobe_cluster -f 4 --lobes 2 --clusters 2 twill.vdb twill_4x_lobes.vdb
  vdb_optimize_weights twill.vdb twill_4x_lobes.vdb twill_4x_opt.vdb -v
  vdb_optimize_weights --log run.jsonl --checkpoint run.ckpt full.vdb lobes.vdb out.vdb
  vdb_optimize_weights --resume run.ckpt --checkpoint run.ckpt full.vdb lobes.vdb out.vdb
  vdb_lobe_cluster -f 4 --clusters 5 --jitter 0.02 ball.vdb - | vdb_optimize_weights ball.vdb - - | vdb_render - -o b.exr
  scripts/plot_convergence.py run.jsonl convergence.png

FULL is the full-resolution medium (a file: its bytes, with the --grid mapping its foreign grids are
read with, address the reference cache), LOBES the output of vdb_lobe_cluster on it. OUT is LOBES with every lobe{j}_weight multiplied by the factor
of its voxel's cluster (Eq. 12; Eq. 19 with colour scales) and the metadata weight_factors; any
renderer that reads lobes renders it. Training: the views of --training-views x the lights of
--training-lights (default: from above, over a ground; the paper's set is --training-views faces
--training-lights sh1), --resolution pixels on the long side; the error is Eq. 14 over restricted means,
its gradient Eq. 16 from gradient images of the same paths. Step sizes a/(t+b) (Eq. 18) are tuned
from the first iteration. See docs/optimize.md.)";

struct Flags {
  WeightOptimizationOptions options;
  std::string report, colour = "auto", interp = "nearest", cache, steps = "newton";
  bool per_channel = false, no_cache = false, verbose = false;
};

void addFlags(CLI::App& app, Flags& f) {
  WeightOptimizationOptions& o = f.options;
  app.add_option("FULL", o.full, "full-resolution medium (.vdb file)")->required();
  app.add_option("LOBES", o.lobes, "its multi-lobe reduction from vdb_lobe_cluster; - reads stdin")->required();
  app.add_option("OUT", o.output, "output medium (.vdb); - writes a VDB stream to stdout")->required();
  app.add_option("--iterations", o.optimizer.max_iterations, "most SGD iterations")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--min-iterations", o.optimizer.min_iterations, "fewest iterations before the convergence test")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--tolerance", o.optimizer.tolerance,
                 "converged when no factor moved by more than this (relative) in each of the last 3 iterations")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--spp", o.optimizer.spp, "samples per pixel of each training image per iteration (two halves)")
      ->check(CLI::Range(2, 1 << 20))->capture_default_str();
  app.add_option("--reference-spp", o.references.reference_spp, "samples per pixel of the reference images")
      ->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--resolution", o.resolution, "training images: pixels on the long side")
      ->check(CLI::Range(8, 4096))->capture_default_str();
  app.add_option("--training-lights", o.training_lights,
                 "lights of the training set, +-separated: sh0, sh1 (bands 0-1, the paper's), sh2, sun, and ground (a "
                 "ground under the medium)")
      ->capture_default_str();
  app.add_option("--training-views", o.training_views,
                 "views of the training images: sides +x ... -z, box corners +x+y+z ... -x-y-z, faces, corners, "
                 "upper-corners (the paper's: faces)")
      ->capture_default_str();
  app.add_option("--colour", f.colour,
                 "auto (colour scales when LOBES's weights differ between channels), grey or colour-scales (Eq. 19)")
      ->check(CLI::IsMember({"auto", "grey", "colour-scales"}))->capture_default_str();
  app.add_flag("--per-channel", f.per_channel, "optimise w per RGB channel instead of colour scales (Fig. 15)");
  app.add_option("--seed", o.optimizer.seed, "random seed: same seed, same factors, whatever -j")->capture_default_str();
  app.add_option("--interp", f.interp, "voxel lookup of the renders: nearest (default) or trilinear")
      ->check(CLI::IsMember({"nearest", "trilinear"}));
  app.add_option("--steps", f.steps, "step rule: newton (Gauss-Newton matrix from the first iteration) or diagonal "
                                     "(per-factor a_kj, the paper's form); docs/optimize.md")
      ->check(CLI::IsMember({"newton", "diagonal"}))->capture_default_str();
  app.add_option("--step-b", o.optimizer.step_b, "b of the step size a / (t + b), Eq. 18")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--step-scale", o.optimizer.step_scale, "multiplies the tuned a of Eq. 18")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--cache", f.cache, "folder of cached reference images (default: $VDBAPPEAR_CACHE, else "
                                     "$XDG_CACHE_HOME/vdbappear, else ~/.cache/vdbappear)");
  app.add_flag("--full-precision", o.full_precision,
               "render FULL's references from its float grids, read whole, instead of its compact form (half-float "
               "albedo and S, read in pieces: docs/rendering.md)");
  app.add_flag("--no-cache", f.no_cache, "render the references without reading or writing a cache");
  app.add_option("--log", o.log, "JSON-lines log: one line per iteration (t, E, factors, gradient, steps, seconds)");
  app.add_option("--checkpoint", o.checkpoint, "write the optimiser's state here after every iteration");
  app.add_option("--resume", o.resume, "continue from a checkpoint of the same inputs and settings")
      ->check(CLI::ExistingFile);
  app.add_option("--report", f.report, "write a JSON report; - for stdout");
  app.add_flag("-v,--verbose", f.verbose, "print the factors, errors and timings to stderr");
  tool::addGridMapping(app, o.full_mapping);  // FULL's grids; LOBES is vdb_lobe_cluster's output
}

void printSummary(const WeightOptimizationResult& result) {
  const nlohmann::json& r = result.record;
  const nlohmann::json& s = r["seconds"];
  fmt::print(stderr, "{}: {} iterations{}, E {:.4g} (naive) -> {:.4g}; references {:.1f} s ({} of {} cached), "
                     "optimisation {:.1f} s\n",
             kTool, r["iterations"].get<int>(), r["converged"].get<bool>() ? " (converged)" : "",
             r["E_naive"].get<double>(), r["E_final"].get<double>(), s["references"].get<double>(), result.cache_hits,
             result.references, s["optimisation"].get<double>() + s["final_evaluation"].get<double>());
  const nlohmann::json& factors = r["factors"];
  for (std::size_t k = 0; k < factors["w"].size(); ++k) {
    std::string line = fmt::format("{}:   cluster {}: w =", kTool, k);
    for (const auto& w : factors["w"][k]) line += fmt::format(" ({:.4f}, {:.4f}, {:.4f})", w[0].get<double>(), w[1].get<double>(), w[2].get<double>());
    const auto& sk = factors["s"][k];
    line += fmt::format("  s = ({:.4f}, {:.4f}, {:.4f})", sk[0].get<double>(), sk[1].get<double>(), sk[2].get<double>());
    fmt::print(stderr, "{}\n", line);
  }
}

// The flags' checks, and the options they set; the outputs are checked on the root only, which alone
// writes them.
void checkFlags(Flags& flags, bool root) {
  WeightOptimizationOptions& o = flags.options;
  if (root) {
    tool::checkOutputs(o.lobes, o.output, flags.report);
    tool::checkDistinct(o.full, o.output, flags.report);
  }
  for (const std::string* file : {&o.log, &o.checkpoint}) {
    if (file->empty()) continue;
    for (const std::string& other : {o.full, o.lobes, o.output, flags.report})
      if (*file == other) throw std::runtime_error(fmt::format("{}: named twice among the inputs and outputs", *file));
    if (root) checkWritable(*file);
  }
  if (flags.per_channel && flags.colour != "auto")
    throw std::runtime_error("--per-channel excludes --colour (it replaces the colour scales)");
  if (flags.per_channel) o.mode = ColourMode::kPerChannel;
  else if (flags.colour != "auto") o.mode = parseColourMode(flags.colour);
  if (o.optimizer.min_iterations > o.optimizer.max_iterations) o.optimizer.min_iterations = o.optimizer.max_iterations;
  o.interpolation = parseInterpolation(flags.interp);
  o.optimizer.step_rule = parseStepRule(flags.steps);
  o.cache = flags.no_cache ? "" : (flags.cache.empty() ? defaultCacheFolder() : flags.cache);
}

}  // namespace

int main(int argc, char** argv) {
  const std::unique_ptr<ProcessGroup> group = joinProcessGroup(&argc, &argv);
  CLI::App app("Optimises the lobe-weight factors of a multi-lobe downsampled medium by stochastic gradient "
               "descent on path-traced gradient images (§6.3-6.4, Appendix A of the downsampling paper).",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Flags flags;
  addFlags(app, flags);
  tool::ThreadLimit threads(app);
  flags.options.history_line = historyLine(kTool, argc, argv);

  return tool::run(app, argc, argv, *group, [&] {
    threads.apply();
    WeightOptimizationOptions& o = flags.options;
    group->together([&] { checkFlags(flags, group->isRoot()); });
    o.group = group.get();
    const auto note = [&](const std::string& line) {
      if (flags.verbose || line.rfind("resumed", 0) == 0) fmt::print(stderr, "{}: {}\n", kTool, line);
    };
    const WeightOptimizationResult result = optimizeWeights(o, note);
    if (!group->isRoot()) return 0;
    if (flags.verbose) printSummary(result);
    if (!flags.report.empty()) {
      nlohmann::json report = result.record;
      report["cache_hits"] = result.cache_hits;
      report["references"] = result.references;
      report["full"] = o.full;
      report["lobes"] = o.lobes;
      report["output"] = o.output;
      tool::writeJsonReport(flags.report, report);
    }
    return 0;
  });
}
