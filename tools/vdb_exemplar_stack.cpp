// vdb_exemplar_stack: exemplar blocks stacked into one volume, so that one run of the downsampling
// pipeline serves every model built from them; cut back into reduced blocks; models assembled from
// blocks (§7 of Zhao et al. 2016, "Downsampling Scattering Parameters for Rendering Anisotropic Media").
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/modularity/assembly.h"
#include "libvdbappear/modularity/exemplar_layout.h"
#include "libvdbappear/modularity/stacking.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <sstream>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_exemplar_stack";

constexpr const char* kExamples = R"(Examples:
  vdb_make_medium exemplars --count 6 --layout 8x8 -o blocks.vdb
  vdb_exemplar_stack stack --seed 3 blocks.vdb stacked.vdb
  vdb_lobe_cluster -f 4 --lobes 2 --clusters 2 stacked.vdb stacked_lobes.vdb
  vdb_optimize_weights stacked.vdb stacked_lobes.vdb stacked_opt.vdb
  vdb_exemplar_stack split stacked_opt.vdb blocks_4x.vdb
  vdb_exemplar_stack assemble blocks.vdb model.vdb                          # reference
  vdb_exemplar_stack assemble blocks_4x.vdb model_4x.vdb                    # fast model, same layout
  vdb_exemplar_stack assemble --layout damask.json blocks_4x.vdb damask_4x.vdb
  vdb_exemplar_stack assemble --instanced --layout huge.json blocks_4x.vdb huge.vdb && vdb_render huge.vdb -o huge.exr

stack: the N blocks (side by side along x, docs/medium.md section 6b) are placed in the slots of an
exemplar volume (sheets: one square layer; other blocks: near-cubic; or --shape), randomly under
--seed (or --order sorted, or --order 2,0,1,...); the placement is the grid exemplar_stacking.
split: any output of the pipeline on a stacked volume back to N blocks side by side, at its
resolution. assemble: block (i,j,k) of the model holds the
exemplar its layout names: the block set's exemplar_layout grid, or --layout (a medium with such a
grid, or JSON: [[[id, ...], ...], ...], sheets (z) of rows (y) of ids (x); a 2-D array is one
sheet; -1 leaves a block empty). See docs/modularity.md.)";

struct Options {
  GridMapping mapping;  // --grid
  std::string input, output, report, layout, order = "random", shape;
  std::uint64_t seed = 1;
  bool verbose = false, instanced = false;
};

StackOptions stackOptions(const Options& options) {
  StackOptions stack;
  stack.seed = options.seed;
  if (!options.shape.empty()) {
    char x1 = 0, x2 = 0, rest = 0;
    auto& n = stack.shape;
    if (std::sscanf(options.shape.c_str(), "%d%c%d%c%d%c", &n[0], &x1, &n[1], &x2, &n[2], &rest) != 5 || x1 != 'x' ||
        x2 != 'x' || n[0] < 1 || n[1] < 1 || n[2] < 1)
      throw std::invalid_argument(fmt::format("--shape '{}': expected NXxNYxNZ slots, each at least 1", options.shape));
  }
  if (options.order == "random") return stack;
  if (options.order == "sorted") {
    stack.order = StackOptions::Order::Sorted;
    return stack;
  }
  stack.order = StackOptions::Order::Given;
  std::stringstream list(options.order);
  for (std::string id; std::getline(list, id, ',');) {
    std::size_t used = 0;
    int value = -1;
    try {
      value = std::stoi(id, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != id.size() || id.empty())
      throw std::invalid_argument(fmt::format("--order '{}': expected random, sorted or a comma-separated list of "
                                              "exemplar ids", options.order));
    stack.permutation.push_back(value);
  }
  return stack;
}

ExemplarLayout layoutFor(const Options& options, const Medium& blocks) {
  if (options.layout.empty()) return layoutOfMedium(blocks);
  if (options.layout.size() > 5 && options.layout.substr(options.layout.size() - 5) == ".json")
    return readLayoutJson(options.layout);
  const MediumPtr layout_medium = readMedium(options.layout);
  checkLayoutMedium(*layout_medium, blocks);
  return layoutOfMedium(*layout_medium);
}

int runCommand(const std::string& command, const Options& options, const std::string& history) {
  tool::checkOutputs(options.input, options.output, options.report);
  if (!options.layout.empty()) tool::checkDistinct(options.layout, options.output, options.report);
  Stopwatch clock;
  const MediumPtr in = tool::readInputMedium(kTool, options.input, options.mapping);
  const double read_seconds = clock.lap();
  MediumPtr out;
  nlohmann::json details;
  if (command == "stack") {
    const StackOptions stack = stackOptions(options);
    out = stackExemplars(*in, stack);
    const BlockCounts shape = stackShapeFor(*in, stack);
    details["order"] = options.order;
    details["shape"] = shape;
    if (options.verbose) fmt::print(stderr, "{} stack: {}x{}x{} slots\n", kTool, shape[0], shape[1], shape[2]);
    details["seed"] = options.seed;
  } else if (command == "split") {
    out = splitStacked(*in);
  } else {
    const ExemplarLayout layout = layoutFor(options, *in);
    out = options.instanced ? instancedModel(*in, layout) : assembleModel(*in, layout);
    details["layout"] = {{"source", options.layout.empty() ? options.input : options.layout},
                         {"blocks", {layout.width, layout.height, layout.depth}}};
    details["instanced"] = options.instanced;
  }
  const double work_seconds = clock.lap();
  writeMedium(*out, options.output, history);
  const double write_seconds = clock.lap();

  const MediumSummary in_summary = summarize(*in), out_summary = summarize(*out);
  if (options.verbose)
    fmt::print(stderr, "{} {}: {} -> {}: {} -> {} active voxels; read {:.2f} s, {} {:.2f} s, write {:.2f} s\n", kTool,
               command, options.input, options.output, in_summary.active_voxels, out_summary.active_voxels,
               read_seconds, command, work_seconds, write_seconds);
  if (!options.report.empty()) {
    nlohmann::json report = {{"tool", kTool},
                             {"version", kVersion},
                             {"command", command},
                             {"input", tool::summaryJson(in_summary, options.input)},
                             {"output", tool::summaryJson(out_summary, options.output)},
                             {"seconds", {{"read", read_seconds}, {command, work_seconds}, {"write", write_seconds}}}};
    report.update(details);
    tool::writeJsonReport(options.report, report);
  }
  return 0;
}

CLI::App* addCommand(CLI::App& app, const std::string& name, const std::string& what, const std::string& in_name,
                     Options& options) {
  CLI::App* command = app.add_subcommand(name, what);
  command->add_option(in_name, options.input, "input medium (.vdb); - reads a VDB stream from stdin")->required();
  command->add_option("OUT", options.output, "output medium (.vdb); - writes a VDB stream to stdout")->required();
  return command;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Exemplar blocks for modular models (§7 of the downsampling paper): stack them into one volume that "
               "the pipeline reduces and optimises once, split the result back into reduced blocks, assemble any "
               "model from blocks.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  app.require_subcommand(1);
  app.fallthrough();
  Options options;
  CLI::App* stack = addCommand(app, "stack", "N blocks side by side -> one exemplar volume (sheets: one square layer)", "BLOCKS", options);
  stack->add_option("--order", options.order,
                    "placement of the exemplars in the volume's slots (x fastest): random (default), sorted, or a "
                    "comma-separated permutation of 0..N-1");
  stack->add_option("--shape", options.shape,
                    "slots of the exemplar volume along x, y, z, as NXxNYxNZ (default: the most cubic volume; 3x2x1 "
                    "puts six sheets side by side)");
  stack->add_option("--seed", options.seed, "seed of the random placement (default 1)")->check(CLI::NonNegativeNumber);
  addCommand(app, "split", "a stacked volume (after any step of the pipeline) -> N blocks side by side", "STACKED",
             options);
  CLI::App* assemble = addCommand(app, "assemble", "blocks -> the model that a layout describes", "BLOCKS", options);
  assemble->add_option("--layout", options.layout,
                       "the layout: a .json file, or a medium with an exemplar_layout grid (default: the block set's own)");
  assemble->add_flag("--instanced", options.instanced,
                     "write the block set and the layout only (exemplar_kind instanced); vdb_render looks the model's "
                     "voxels up through the layout, in memory that grows with the block set, not the model");
  app.add_flag("-v,--verbose", options.verbose, "print voxel counts and timings to stderr");
  app.add_option("--report", options.report, "write a JSON report (voxel counts, bytes, timings) to this file");
  tool::addGridMapping(app, options.mapping);
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    return runCommand(app.get_subcommands().front()->get_name(), options, history);
  });
}
