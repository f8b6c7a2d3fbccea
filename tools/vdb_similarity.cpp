// vdb_similarity: high-order similarity relations (Zhao, Ramamoorthi and Bala 2014, "High-Order
// Similarity Relations in Radiative Transfer"): altered scattering parameters that render faster and
// look the same.
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/io/phase_table_file.h"
#include "libvdbappear/similarity/legendre_moments.h"
#include "libvdbappear/similarity/similarity_medium.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <stdexcept>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_similarity";

constexpr const char* kExamples = R"(Examples:
  vdb_similarity --hg 0.9 --json                      one phase function: alpha, order, table as JSON
  vdb_similarity --hg 0.95 --alpha 0.2 --max-order 3
  vdb_similarity --hg 0.9 --order-rule support --json  the order rule of Algorithm 1 as printed (§7.3)
  vdb_similarity --table measured.txt --json > altered.json
  vdb_similarity cloud.vdb cloud_altered.vdb -v       a medium with hg_g (grid or metadata) or phase_table
  vdb_make_medium cloud -o - | vdb_similarity - - | vdb_render - -o fast.exr

sigma_a* = sigma_a, sigma_s* = alpha sigma_s; the altered phase function f* keeps the reduced
attenuation sigma_a + sigma_s (1 - f_n) of every order n <= N (Eq. 23). Of the orders <= --max-order
that Theorem 1 allows, N is the one whose alpha f* + (1 - alpha) delta is closest to f (Wasserstein-1
distance); with --order-rule support, the highest whose table is not overfitting (support >=
--support-ratio times the original's, §7.3). f* is tabulated on --bins bins of mu by the QP of
Eq. (31), solved exactly. Default alpha: max(0.3, 1 - f1) per phase function (§7.2), at most 1.
Colour: exact for a grey albedo; with RGB albedo, absorption is kept in every channel and the
relations hold for a reference albedo (docs/similarity.md). A per-voxel hg_g is quantised so that every Legendre moment used moves by at
most --moment-tolerance. Tables read with --table: JSON ("table" array) or numbers, ascending mu.)";

struct Options {
  GridMapping mapping;  // --grid
  std::string input, output, report, table_file;
  std::optional<double> hg_g;
  MediumSimilarityOptions medium;
  bool json = false, verbose = false;
};

nlohmann::json rejectedJson(const std::vector<RejectedOrder>& rejected) {
  nlohmann::json list = nlohmann::json::array();
  for (const RejectedOrder& r : rejected)
    list.push_back({{"order", r.order}, {"support", r.support}, {"distance", r.distance}, {"reason", r.reason}});
  return list;
}

nlohmann::json alteredPhaseJson(const AlteredPhase& a, const SimilarityOptions& o) {
  return {{"alpha", a.alpha},
          {"order", a.order},
          {"moments", a.moments},
          {"support", a.support},
          {"input_support", a.input_support},
          {"support_ratio", o.support_ratio},
          {"support_below_threshold", a.support_below_threshold},
          {"order_rule", orderRuleName(o.order_rule)},
          {"distance", a.distance},
          {"max_order", o.max_order},
          {"existence_margins", a.existence_margins},
          {"rejected", rejectedJson(a.rejected)},
          {"table_moments", tableMoments(a.table, o.max_order)},
          {"bins", int(a.table.size())},
          {"table", a.table}};
}

// One material: --hg G or --table FILE.
int alterOnePhase(const Options& options) {
  const SimilarityOptions& o = options.medium.phase;
  const bool hg = options.hg_g.has_value();
  const PhaseMoments phase = hg ? henyeyGreensteinPhaseMoments(*options.hg_g, o.max_order)
                                : tablePhaseMoments(readPhaseTableFile(options.table_file), o.max_order);
  Stopwatch clock;
  const AlteredPhase altered = computeAlteredPhase(phase, o);
  const double seconds = clock.lap();
  nlohmann::json json = alteredPhaseJson(altered, o);
  json["input"] = hg ? nlohmann::json{{"hg_g", *options.hg_g}} : nlohmann::json{{"table", options.table_file}};
  json["input"]["moments"] = phase.moments;
  json["seconds"] = seconds;
  if (options.json) {
    std::cout << json.dump(2) << "\n";
    return 0;
  }
  fmt::print("alpha {:g}: sigma_s* = {:g} sigma_s, sigma_a* = sigma_a\n", altered.alpha, altered.alpha);
  fmt::print("order {} (f1 = {:.6g} -> f1* = {:.6g}); table of {} bins, support {:.3f} (original {:.3f})\n", altered.order,
             phase.moments[1], altered.moments[1], altered.table.size(), altered.support, altered.input_support);
  for (const RejectedOrder& r : altered.rejected) fmt::print("  order {} rejected: {}\n", r.order, r.reason);
  if (altered.support_below_threshold) fmt::print("  every order overfits: kept the widest table\n");
  fmt::print("solved in {:.1f} ms; --json prints the table\n", 1e3 * seconds);
  return 0;
}

nlohmann::json tablesJson(const std::vector<AlteredTable>& tables) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t t = 0; t < tables.size(); ++t) {
    const AlteredTable& a = tables[t];
    list.push_back({{"id", t}, {"source", a.source}, {"f1", a.f1}, {"voxels", a.voxels}, {"alpha", a.phase.alpha},
                    {"order", a.phase.order}, {"support", a.phase.support}, {"distance", a.phase.distance},
                    {"support_below_threshold", a.phase.support_below_threshold}, {"rejected", rejectedJson(a.phase.rejected)}});
  }
  return list;
}

void printSummary(const MediumSimilarityResult& r, double seconds) {
  fmt::print(stderr, "{}: {} voxels, {} phase function(s) altered in {:.2f} s\n", kTool, r.voxels, r.tables.size(), seconds);
  if (r.g_levels > 0)
    fmt::print(stderr, "{}:   hg_g quantised on {} levels: moment bound {:.2g}, largest moment error found {:.2g}\n", kTool,
               r.g_levels, r.moment_tolerance, r.max_moment_error);
  const std::size_t shown = std::min<std::size_t>(r.tables.size(), 8);
  for (std::size_t t = 0; t < shown; ++t) {
    const AlteredTable& a = r.tables[t];
    fmt::print(stderr, "{}:   table {} ({}): alpha {:.3g}, order {}, support {:.3f}, {} voxels\n", kTool, t, a.source,
               a.phase.alpha, a.phase.order, a.phase.support, a.voxels);
  }
  if (shown < r.tables.size()) fmt::print(stderr, "{}:   ... {} more tables (--report lists them)\n", kTool, r.tables.size() - shown);
  fmt::print(stderr, "{}:   largest relative error of sigma_tr,1 from colour: {:.3g}\n", kTool, r.max_reduced_attenuation_error);
}

// A medium: IN OUT.
int alterMediumFile(const Options& options, const std::string& history) {
  tool::checkOutputs(options.input, options.output, options.report);
  Stopwatch clock;
  const MediumPtr input = tool::readInputMedium(kTool, options.input, options.mapping);
  const double read_seconds = clock.lap();
  MediumSimilarityResult result;
  {
    ProgressBar progress("altering phase functions", 0);
    result = alterMedium(*input, options.medium, &progress);
  }
  const double alter_seconds = clock.lap();
  for (const auto& note : result.notes) fmt::print(stderr, "{}: note: {}\n", kTool, note);
  writeMedium(*result.medium, options.output, history);
  const double write_seconds = clock.lap();
  if (options.verbose) printSummary(result, alter_seconds);
  if (!options.report.empty()) {
    const SimilarityOptions& o = options.medium.phase;
    tool::writeJsonReport(options.report,
                          {{"tool", kTool},
                           {"version", kVersion},
                           {"input", tool::summaryJson(summarize(*input), options.input)},
                           {"output", tool::summaryJson(summarize(*result.medium), options.output)},
                           {"alpha_option", o.alpha > 0 ? nlohmann::json(o.alpha) : nlohmann::json("max(0.3, 1 - f1)")},
                           {"max_order", o.max_order},
                           {"support_ratio", o.support_ratio},
                           {"order_rule", orderRuleName(o.order_rule)},
                           {"bins", o.bins},
                           {"voxels", result.voxels},
                           {"g_levels", result.g_levels},
                           {"moment_bound", result.moment_tolerance},
                           {"max_moment_error", result.max_moment_error},
                           {"max_reduced_attenuation_error", result.max_reduced_attenuation_error},
                           {"tables", tablesJson(result.tables)},
                           {"notes", result.notes},
                           {"seconds", {{"read", read_seconds}, {"alter", alter_seconds}, {"write", write_seconds}}}});
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("High-order similarity relations (Zhao, Ramamoorthi and Bala 2014): altered scattering parameters "
               "(fewer, wider scattering events) that render faster and look the same.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options options;
  SimilarityOptions& o = options.medium.phase;
  std::string order_rule = orderRuleName(o.order_rule);
  auto* in = app.add_option("IN", options.input, "input medium (.vdb); - reads a VDB stream from stdin");
  app.add_option("OUT", options.output, "output medium (.vdb); - writes a VDB stream to stdout");
  auto* hg = app.add_option("--hg", options.hg_g, "one material: a Henyey-Greenstein phase function with this g")
                 ->check(CLI::Range(-0.999999, 0.999999));
  auto* table = app.add_option("--table", options.table_file, "one material: a tabulated phase function (JSON or numbers, ascending mu)")
                    ->excludes(hg);
  in->excludes(hg)->excludes(table);
  app.add_option("--alpha", o.alpha, "sigma_s* / sigma_s in (0,1] (default: max(0.3, 1 - f1) per phase function)")
      ->check(CLI::Range(1e-6, 1.0));
  app.add_option("--max-order", o.max_order, "N0: the highest order of the relations (Algorithm 1)")
      ->check(CLI::Range(1, 12))
      ->capture_default_str();
  app.add_option("--support-ratio", o.support_ratio,
                 "beta of §7.3 (--order-rule support): reject a table with less support than beta times the original's")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--order-rule", order_rule,
                 "how the order is chosen: distance (the order whose f* is closest to f in the Wasserstein-1 distance, "
                 "never the classic order 1's worse; docs/similarity.md) or support (Algorithm 1 as printed: the highest "
                 "order not overfitting, §7.3)")
      ->check(CLI::IsMember({"support", "distance"}))
      ->capture_default_str();
  app.add_option("--bins", o.bins, "k: bins of the altered tables (Eq. 30)")->check(CLI::Range(16, 4096))->capture_default_str();
  app.add_option("--moment-tolerance", options.medium.moment_tolerance,
                 "per-voxel hg_g: quantise g so that every Legendre moment up to N0 moves by at most this")
      ->check(CLI::Range(1e-6, 0.1))
      ->capture_default_str();
  app.add_flag("--json", options.json, "one material: print the result as one JSON object");
  app.add_option("--report", options.report, "media: write a JSON report (tables, orders, errors, timings) to this file");
  app.add_flag("-v,--verbose", options.verbose, "media: print the tables and errors to stderr");
  tool::addGridMapping(app, options.mapping);
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    o.order_rule = parseOrderRule(order_rule);
    const bool one_phase = options.hg_g || !options.table_file.empty();
    if (one_phase) {
      if (!options.report.empty()) throw std::invalid_argument("--report is for media; --json prints the one-material result");
      return alterOnePhase(options);
    }
    if (options.input.empty() || options.output.empty())
      throw std::invalid_argument("give a medium IN and an output OUT, or --hg G / --table FILE for one material");
    if (options.json) throw std::invalid_argument("--json is for one material (--hg or --table); media write --report");
    return alterMediumFile(options, history);
  });
}
