// vdb_sggx_downsample: naive downsampling of density, albedo and SGGX phase functions
// (Eq. 5-6 of Zhao et al. 2016, "Downsampling Scattering Parameters for Rendering Anisotropic Media").
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/downsample/streamed_downsample.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <map>
#include <optional>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_sggx_downsample";

constexpr const char* kExamples = R"(Examples:
  vdb_sggx_downsample --factor 4 twill.vdb twill_4x.vdb
  vdb_sggx_downsample --factor 2 in.vdb - | vdb_sggx_downsample --factor 2 - out.vdb
  vdb_sggx_downsample -f 8 --s-weight density -v --report report.json in.vdb out.vdb
  vdb_sggx_downsample -f 2 --memory 2 -v twill1024.vdb twill512.vdb

A file is read in slabs along x, each as wide as fits in --memory (a quarter of the machine's memory
by default, at most 4 GB; a slab too large is cut along y and z), its topology indexed once a 128^3 node at a time (the 1024^3 twill in
0.13 GB, about 700 bytes a node); the downsampled slabs wait on scratch files in OUT's folder (removed
as they are made: nothing is left behind) and are written leaf by leaf. The result is the same, bit
for bit, as reading the medium whole (--in-core), which stdin (-) and files that a grid mapping
(--grid, --from) applies to are. See docs/scaling.md.

Output voxel I holds input voxels F*I .. F*I+F-1 on each axis; the world region is preserved.
density: mean over the F^3 children, empty ones counting 0 (Eq. 6). albedo: density-weighted mean
(Eq. 6). S: mean over children with density > 0 (Eq. 5, --s-weight count) or density-weighted
(--s-weight density). See docs/downsampling.md.)";

struct Options {
  GridMapping mapping;  // --grid
  std::string input, output, report;
  DownsampleOptions downsample;
  tool::SlabReading slabs;  // --memory, --in-core
  bool verbose = false;
};

// The file read in slabs (docs/scaling.md), or nullopt where it must be read whole.
std::optional<StreamedDownsample> streamed(const Options& options) {
  const auto result = options.slabs.run(kTool, options.input, "downsampling slabs", options.verbose,
                                        [&](std::uint64_t budget, std::string* why_not, ProgressBar* progress) {
                                          return downsampleNaiveStreamed(options.input, options.mapping, options.downsample, budget,
                                                      why_not, progress, options.output);
                                        });
  if (result && options.verbose)
    fmt::print(stderr, "{}: read in {} piece{} (budget {:.3g} GB; the largest piece's grids held {:.3g} GB)\n",
               kTool, result->slabs, result->slabs == 1 ? "" : "s", options.slabs.budgetBytes() / 1e9, result->largest_slab_bytes / 1e9);
  return result;
}

int downsample(const Options& options, const std::string& history) {
  tool::checkOutputs(options.input, options.output, options.report);
  Stopwatch clock;
  DownsampleResult result;
  MediumSummary in, out;
  double read_seconds = 0, downsample_seconds = 0;
  if (auto slabs = streamed(options)) {  // reading and downsampling interleave: one time for both
    result = std::move(slabs->result);
    in = std::move(slabs->input);
    out = std::move(slabs->output);
    downsample_seconds = clock.lap();
  } else {
    const MediumPtr fine = tool::readInputMedium(kTool, options.input, options.mapping);
    read_seconds = clock.lap();
    ProgressBar progress("downsampling", 0);
    result = downsampleNaive(*fine, options.downsample, &progress);
    in = summarize(*fine);
    out = summarize(*result.medium);
    downsample_seconds = clock.lap();
  }
  for (const auto& warning : result.warnings) fmt::print(stderr, "{}: warning: {}\n", kTool, warning);

  writeMedium(*result.medium, options.output, history);  // in slabs: leaf by leaf, from disk
  const double write_seconds = clock.lap();

  if (options.verbose) {
    fmt::print(stderr, "{}: {} -> {}: factor {}, {} -> {} active voxels ({:.1f}x fewer), {:.1f} -> {:.1f} MB in memory\n",
               kTool, options.input, options.output, options.downsample.factor, in.active_voxels, out.active_voxels,
               double(in.active_voxels) / double(std::max<std::uint64_t>(1, out.active_voxels)),
               in.memory_bytes / 1e6, out.memory_bytes / 1e6);
    fmt::print(stderr, "{}: read {:.3f} s, downsample {:.3f} s, write {:.3f} s\n", kTool, read_seconds,
               downsample_seconds, write_seconds);
  }
  if (!options.report.empty()) {
    tool::writeJsonReport(options.report,
                          {{"tool", kTool},
                           {"version", kVersion},
                           {"factor", options.downsample.factor},
                           {"s_weight", options.downsample.s_weighting == SggxWeighting::Count ? "count" : "density"},
                           {"input", tool::summaryJson(in, options.input)},
                           {"output", tool::summaryJson(out, options.output)},
                           {"seconds", {{"read", read_seconds}, {"downsample", downsample_seconds}, {"write", write_seconds}}},
                           {"warnings", result.warnings}});
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Naive downsampling of a medium's density, albedo and SGGX phase functions "
               "(Eq. 5-6 of the downsampling paper): the baseline other reductions are compared with.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options options;
  app.add_option("IN", options.input, "input medium (.vdb); - reads a VDB stream from stdin")->required();
  app.add_option("OUT", options.output, "output medium (.vdb); - writes a VDB stream to stdout")->required();
  app.add_option("-f,--factor", options.downsample.factor,
                 fmt::format("downsampling factor F, an integer in 2..{}", kMaxDownsampleFactor))
      ->check(CLI::Range(2, kMaxDownsampleFactor))
      ->capture_default_str();
  const std::map<std::string, SggxWeighting> weightings{{"count", SggxWeighting::Count},
                                                        {"density", SggxWeighting::Density}};
  app.add_option("--s-weight", options.downsample.s_weighting,
                 "how children's S are averaged: count (Eq. 5, mean over children with density > 0) or "
                 "density (density-weighted mean)")
      ->transform(CLI::CheckedTransformer(weightings, CLI::ignore_case))
      ->default_str("count");
  options.slabs.addFlags(app);
  app.add_flag("-v,--verbose", options.verbose, "print voxel counts, memory and timings to stderr");
  app.add_option("--report", options.report, "write a JSON report (voxel counts, bytes, timings) to this file");
  tool::addGridMapping(app, options.mapping);
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    return downsample(options, history);
  });
}
