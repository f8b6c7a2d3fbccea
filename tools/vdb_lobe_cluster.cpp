// vdb_lobe_cluster: multi-lobe SGGX fits per downsampled voxel and voxel clustering
// (§5 and §6.2 of Zhao et al. 2016, "Downsampling Scattering Parameters for Rendering Anisotropic Media").
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/lobes/lobe_order.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/lobes/streamed_multi_lobe.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_lobe_cluster";

constexpr const char* kExamples = R"(Examples:
  vdb_lobe_cluster --factor 4 twill.vdb twill_4x_lobes.vdb
  vdb_lobe_cluster -f 4 --lobes 2 --clusters 2 --report lobes.json twill.vdb out.vdb
  vdb_lobe_cluster -f 4 --clusters 5 --jitter 0.02 hairy-ball.vdb - | vdb_render - -o ball.exr
  vdb_lobe_cluster -f 4 --lobes 2 --clusters 2 --memory 2 -v twill1024.vdb twill256_lobes.vdb

A file is read in slabs along x, each as wide as fits in --memory (a quarter of the machine's memory
by default, at most 4 GB; a slab too large is cut along y and z), in two passes: each slab's lobes are fitted and the slab parked on disk
while its albedos join the clustering's table; then each is read back, its lobes ordered and weighed,
and written leaf by leaf. Scratch files go in OUT's folder and are removed as they are made. The
result is the same, bit for bit, as reading the medium whole (--in-core), which stdin (-) and files
that a grid mapping (--grid, --from) applies to are. See docs/scaling.md.

The base grids are the naive result (vdb_sggx_downsample --s-weight count). Each output voxel's
children with density > 0 are clustered by K-means on their S (Eq. 10); the lobe count follows
§8.1 (add a lobe while it at least halves the fit error, up to --max-lobes) unless --lobes forces
it. Lobe weights are albedo * fraction (Eq. 11). Voxels are clustered by K-means on albedo and
each cluster's lobes ordered against a reference voxel (Eq. 13). A voxel with fewer lobes than the
file's lobe_count has no active value in the other slots' grids. See docs/lobes.md.)";

struct Options {
  GridMapping mapping;  // --grid
  std::string input, output, report;
  MultiLobeOptions lobes;
  tool::SlabReading slabs;  // --memory, --in-core
  bool verbose = false;
};

// The file read in slabs (docs/scaling.md), or nullopt where it must be read whole.
std::optional<StreamedMultiLobe> streamed(const Options& options) {
  const auto result = options.slabs.run(kTool, options.input, "fitting lobes in slabs", options.verbose,
                                        [&](std::uint64_t budget, std::string* why_not, ProgressBar* progress) {
                                          return downsampleMultiLobeStreamed(options.input, options.mapping, options.lobes, budget,
                                                      why_not, progress, options.output);
                                        });
  if (result && options.verbose)
    fmt::print(stderr,
               "{}: read in {} piece{} (budget {:.3g} GB; the largest piece's grids held {:.3g} GB; {:.3g} GB "
               "parked on disk between the passes; {} distinct albedos clustered, {:.3g} GB)\n",
               kTool, result->slabs, result->slabs == 1 ? "" : "s", options.slabs.budgetBytes() / 1e9, result->largest_slab_bytes / 1e9,
               result->parked_bytes / 1e9, result->distinct_albedos, result->albedo_table_bytes / 1e9);
  return result;
}

nlohmann::json errorTable(const LobeFitStatistics& s) {
  nlohmann::json table = nlohmann::json::array();
  for (int m = 1; m <= int(s.squared_error.size()); ++m)
    table.push_back({{"lobes", m}, {"relative_l2_error", s.relativeError(m)}, {"voxels_fitted_with", s.voxels_with_lobes[m - 1]}});
  return table;
}

nlohmann::json clusterTable(const std::vector<VoxelCluster>& clusters) {
  nlohmann::json table = nlohmann::json::array();
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const VoxelCluster& k = clusters[c];
    table.push_back({{"id", c},
                     {"albedo", {k.albedo.x(), k.albedo.y(), k.albedo.z()}},
                     {"voxels", k.voxels},
                     {"reference_voxel", k.reference},
                     {"reference_lobes", k.reference_lobes}});
  }
  return table;
}

void printSummary(const Options& options, const MultiLobeResult& result, double seconds) {
  const LobeFitStatistics& s = result.statistics;
  fmt::print(stderr, "{}: {} occupied voxels at factor {} in {:.2f} s ({:.0f} voxels/s); {} fit exactly by one lobe\n",
             kTool, s.voxels, options.lobes.factor, seconds, double(s.voxels) / seconds, s.voxels_exact_with_one_lobe);
  for (int m = 1; m <= int(s.squared_error.size()); ++m)
    fmt::print(stderr, "{}:   {} lobe(s): relative L2 error {:.4f}, chosen for {} voxels ({:.1f}%)\n", kTool, m,
               s.relativeError(m), s.voxels_with_lobes[m - 1], 100.0 * double(s.voxels_with_lobes[m - 1]) / double(std::max<std::uint64_t>(1, s.voxels)));
  for (std::size_t c = 0; c < result.clusters.size(); ++c) {
    const VoxelCluster& k = result.clusters[c];
    fmt::print(stderr, "{}:   cluster {}: albedo ({:.3f}, {:.3f}, {:.3f}), {} voxels, reference ({}, {}, {}) with {} lobe(s)\n",
               kTool, c, k.albedo.x(), k.albedo.y(), k.albedo.z(), k.voxels, k.reference[0], k.reference[1],
               k.reference[2], k.reference_lobes);
  }
}

int cluster(const Options& options, const std::string& history) {
  tool::checkOutputs(options.input, options.output, options.report);
  Stopwatch clock;
  MultiLobeResult result;
  MediumSummary in, out;
  double read_seconds = 0, fit_seconds = 0;
  if (auto slabs = streamed(options)) {  // reading and fitting interleave: one time for both
    result = std::move(slabs->result);
    in = std::move(slabs->input);
    out = std::move(slabs->output);
    fit_seconds = clock.lap();
  } else {
    const MediumPtr fine = tool::readInputMedium(kTool, options.input, options.mapping);
    read_seconds = clock.lap();
    ProgressBar progress("fitting lobes", 0);
    result = downsampleMultiLobe(*fine, options.lobes, &progress);
    in = summarize(*fine);
    out = summarize(*result.medium);
    fit_seconds = clock.lap();
  }
  for (const auto& warning : result.warnings) fmt::print(stderr, "{}: warning: {}\n", kTool, warning);

  writeMedium(*result.medium, options.output, history);
  const double write_seconds = clock.lap();
  if (options.verbose) printSummary(options, result, fit_seconds);

  if (!options.report.empty()) {
    const LobeFitStatistics& s = result.statistics;
    const MultiLobeOptions& o = options.lobes;
    tool::writeJsonReport(
        options.report,
        {{"tool", kTool},
         {"version", kVersion},
         {"input", tool::summaryJson(in, options.input)},
         {"output", tool::summaryJson(out, options.output)},
         {"factor", o.factor},
         {"max_lobes", o.fit.max_lobes},
         {"forced_lobes", o.fit.forced_lobes},
         {"keep_ratio", o.fit.keep_ratio},
         {"clusters_asked", o.clustering.clusters},
         {"jitter", o.clustering.jitter},
         {"seed", o.clustering.seed},
         {"voxels", s.voxels},
         {"voxels_exact_with_one_lobe", s.voxels_exact_with_one_lobe},
         {"lobe_count", result.lobe_count},
         {"error_by_lobes", errorTable(s)},
         {"rule_on_whole_medium", s.ruleLobeCount(o.fit.keep_ratio)},
         {"clusters", clusterTable(result.clusters)},
         {"seconds", {{"read", read_seconds}, {"fit", fit_seconds}, {"write", write_seconds}}},
         {"voxels_per_second", double(s.voxels) / fit_seconds},
         {"warnings", result.warnings}});
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Multi-lobe SGGX fits per downsampled voxel and voxel clustering (§5 and §6.2 of the downsampling "
               "paper): writes the naive medium plus lobe grids with naive weights, ready for weight optimisation.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options options;
  MultiLobeOptions& o = options.lobes;
  o.factor = 2;
  app.add_option("IN", options.input, "input medium (.vdb) at full resolution; - reads a VDB stream from stdin")->required();
  app.add_option("OUT", options.output, "output medium (.vdb); - writes a VDB stream to stdout")->required();
  app.add_option("-f,--factor", o.factor, fmt::format("downsampling factor F, an integer in 2..{}", kMaxDownsampleFactor))
      ->check(CLI::Range(2, kMaxDownsampleFactor))
      ->capture_default_str();
  auto* max_lobes = app.add_option("--max-lobes", o.fit.max_lobes, fmt::format("cap on the lobes per voxel, 1..{} (§8.1: 3)", kMaxOrderedLobes))
      ->check(CLI::Range(1, kMaxOrderedLobes))
      ->capture_default_str();
  auto* forced = app.add_option("--lobes", o.fit.forced_lobes,
                                fmt::format("exactly m lobes per voxel, 1..{} (fewer where the children hold fewer "
                                            "distinct S); default: the §8.1 rule", kMaxOrderedLobes))
                     ->check(CLI::Range(1, kMaxOrderedLobes))
                     ->excludes(max_lobes);
  app.add_option("--keep-ratio", o.fit.keep_ratio,
                 "the §8.1 rule adds lobe m+1 while its error is at most this times the error with m lobes")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->excludes(forced);
  app.add_option("-k,--clusters", o.clustering.clusters, "voxel clusters K (K-means on the downsampled albedo, §6.2)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  app.add_option("--jitter", o.clustering.jitter,
                 "standard deviation of Gaussian noise added to each albedo channel before clustering, against "
                 "seams (Fig. 12)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--seed", o.clustering.seed, "seed of the K-means initialisations and the jitter")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  options.slabs.addFlags(app);
  app.add_flag("-v,--verbose", options.verbose, "print the error against the lobe count, the clusters and timings to stderr");
  app.add_option("--report", options.report,
                 "write a JSON report (error against lobe count, lobe counts chosen, clusters, timings) to this file");
  tool::addGridMapping(app, options.mapping);
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    return cluster(options, history);
  });
}
