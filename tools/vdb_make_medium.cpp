// vdb_make_medium: procedural media per docs/medium.md, deterministic under --seed.
#include "tool_main.h"

#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <functional>
#include <map>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_make_medium";

constexpr const char* kExamples = R"(Examples:
  vdb_make_medium --list
  vdb_make_medium weave --res 256 -o weave.vdb
  vdb_make_medium weave --res 256 --layers 4 --yarns 4 -o weave_cube.vdb
  vdb_make_medium random --res 64 --seed 7 -o - | vdb_sggx_downsample -f 2 - small.vdb)";

struct Options {
  std::string kind, output;
  std::map<std::string, const CLI::Option_group*> kind_options;  // options that belong to one kind
  bool list = false, verbose = false;
  int resolution = 128;
  std::uint64_t seed = 1;
  WeaveParams weave;
  RandomMediumParams random;
};

struct Kind {
  std::string description;
  std::function<MediumPtr(const Options&)> make;
};

const std::map<std::string, Kind>& kinds() {
  static const std::map<std::string, Kind> all{
      {"weave",
       {"plain-weave fabric of twisted fibers; warp and weft in two colours; --layers stacks sheets along z",
        [](const Options& o) {
          WeaveParams p = o.weave;
          p.resolution = o.resolution;
          p.seed = o.seed;
          return makePlainWeave(p);
        }}},
      {"random",
       {"random sparse test medium: RGB albedo, random SPD S (near-degenerate included), zero densities",
        [](const Options& o) {
          RandomMediumParams p = o.random;
          p.extent = o.resolution;
          p.seed = o.seed;
          return makeRandomMedium(p);
        }}},
  };
  return all;
}

int make(const Options& options, const std::string& history) {
  if (options.list) {
    for (const auto& [name, kind] : kinds()) fmt::print("{:<8} {}\n", name, kind.description);
    return 0;
  }
  const auto kind = kinds().find(options.kind);
  if (kind == kinds().end()) throw std::runtime_error(fmt::format("unknown kind '{}' (see --list)", options.kind));
  for (const auto& [owner, group] : options.kind_options)
    if (owner != options.kind && group->count_all() > 0)
      throw std::runtime_error(fmt::format("options of kind '{}' given for kind '{}'", owner, options.kind));
  if (options.output.empty()) throw std::runtime_error("no output: give -o OUT (- for stdout)");
  checkWritable(options.output);
  Stopwatch clock;
  const MediumPtr medium = kind->second.make(options);
  const double make_seconds = clock.lap();
  writeMedium(*medium, options.output, history);
  if (options.verbose) {
    const MediumSummary s = summarize(*medium);
    fmt::print(stderr, "{}: {} at {}: {} active voxels, {:.1f} MB in memory, made in {:.2f} s, written in {:.2f} s\n",
               kTool, options.kind, options.resolution, s.active_voxels, s.memory_bytes / 1e6, make_seconds,
               clock.lap());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Writes procedural media (density, albedo, SGGX) for tests, demos and benchmarks.", kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options o;
  app.add_option("KIND", o.kind, "kind of medium (see --list)");
  app.add_option("-o,--output", o.output, "output medium (.vdb); - writes a VDB stream to stdout");
  app.add_flag("--list", o.list, "list the kinds and exit");
  app.add_option("--res", o.resolution, "voxels along the largest side")->check(CLI::Range(8, 4096))->capture_default_str();
  app.add_option("--seed", o.seed, "random seed: same seed, same medium")->capture_default_str();
  app.add_flag("-v,--verbose", o.verbose, "print voxel counts and timings to stderr");
  auto* weave = app.add_option_group("weave", "options of the weave kind");
  weave->add_option("--yarns", o.weave.yarns, "yarns per side")->check(CLI::Range(1, 1024))->capture_default_str();
  weave->add_option("--layers", o.weave.layers, "fabric layers along z")->check(CLI::Range(1, 1024))->capture_default_str();
  weave->add_option("--fiber-density", o.weave.fiber_density, "density inside a fiber, 1/world unit")
      ->check(CLI::PositiveNumber)->capture_default_str();
  weave->add_option("--roughness", o.weave.roughness, "SGGX fiber roughness in (0,1]")
      ->check(CLI::Range(1e-3, 1.0))->capture_default_str();
  auto* random = app.add_option_group("random", "options of the random kind");
  random->add_option("--block-fill", o.random.block_fill, "fraction of 8^3 blocks occupied")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  random->add_option("--voxel-fill", o.random.voxel_fill, "fraction of voxels active in an occupied block")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  o.kind_options = {{"weave", weave}, {"random", random}};
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    return make(o, history);
  });
}
