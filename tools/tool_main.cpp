#include "tool_main.h"

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/util/error_line.h"
#include "libvdbappear/util/system_memory.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <malloc.h>
#include <sstream>

namespace vdbappear::tool {

namespace {
// Grids are read in parallel, and each thread grows the heap in small steps by default; the
// page-fault and brk work then serialises the threads. A 64 MB pad per heap growth measured 0.35 s
// -> 0.29 s for reading a 127 MB medium on 2 cores (scripts/bench_downsample.py).
void tuneAllocator() { mallopt(M_TOP_PAD, 64 << 20); }
}  // namespace

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  return run(app, argc, argv, SoloProcessGroup(), body);
}

int run(CLI::App& app, int argc, char** argv, const ProcessGroup& group, const std::function<int()>& body) {
  tuneAllocator();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (group.isRoot()) return app.exit(e);  // 0 for --help and --version, CLI11's non-zero code for a flag error
    std::ostringstream quiet;
    return app.exit(e, quiet, quiet);
  }
  const std::string where = group.isShared() ? fmt::format(" (rank {} of {})", group.rank(), group.size()) : std::string();
  try {
    return body();
  } catch (const GroupFailure& e) {  // agreed by every rank: printed by the one it happened on
    if (*e.what()) fmt::print(stderr, "{}: error{}: {}\n", app.get_name(), where, errorLine(e.what()));
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: error{}: {}\n", app.get_name(), where, errorLine(e.what()));
    if (group.isShared()) {  // the other ranks would wait for this one forever
      std::fflush(stderr);
      group.abortJob(1);
    }
    return 1;
  }
}

ThreadLimit::ThreadLimit(CLI::App& app) {
  app.add_option("-j,--threads", threads_, "worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
}

ThreadLimit::~ThreadLimit() = default;

void ThreadLimit::apply() {
  if (threads_ > 0)
    control_ = std::make_shared<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads_);
}

namespace {

// Runs parse(text) for flag `flag`; the library's std::invalid_argument becomes CLI11's flag error.
template <typename Parse>
void parseFlag(const char* flag, const std::string& text, Parse&& parse) {
  try {
    parse(text);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(flag, e.what());
  }
}

}  // namespace

void addGridMapping(CLI::App& app, GridMapping& mapping) {
  app.add_option_function<std::vector<std::string>>(
         "--grid",
         [&mapping](const std::vector<std::string>& rules) {
           for (const std::string& text : rules)
             parseFlag("--grid", text, [&](const std::string& t) { addGridRule(mapping, parseGridRule(t)); });
         },
         "read foreign grids as the medium's: ROLE=GRID (albedo=Cd), albedo=R,G,B (three float grids), "
         "albedo=.../GRID (a colour times density, divided by it: albedo=color_r,color_g,color_b/density), "
         "ROLE=GRID:SCALE (density=density:0.5, emission=flame:5), emission=blackbody:GRID[:KELVIN[:INTENSITY]] "
         "(Cycles' blackbody light of a temperature grid); repeatable; roles density, albedo, hg_g, "
         "sggx_diag, sggx_offdiag, emission (docs/medium.md sections 3b, 12)")
      ->type_name("ROLE=GRID");
  app.add_option_function<std::string>(
         "--from",
         [&mapping](const std::string& name) {
           parseFlag("--from", name, [&](const std::string& t) { mapping.preset = parseGridPreset(t); });
         },
         "whose grid names to read for the roles --grid leaves: blender (a smoke cache's "
         "color_r,color_g,color_b/density, or a Volume object's color, as the albedo), houdini (Cd as the albedo), "
         "none (the grids as they are), or auto: either convention, detected in a file without an albedo grid, "
         "with a note of what was mapped (docs/medium.md section 12)")
      ->type_name("auto|blender|houdini|none")
      ->default_str("auto");
}

std::shared_ptr<Medium> readInputMedium(const std::string& tool, const std::string& path, const GridMapping& mapping) {
  MediumPtr medium = readMedium(path, mapping);
  for (const std::string& note : readNotes(*medium)) fmt::print(stderr, "{}: note: {}\n", tool, note);
  return medium;
}

void writeJsonReport(const std::string& path, const nlohmann::json& report) {
  if (path == "-") {
    std::cout << report.dump(2) << "\n";
    return;
  }
  AtomicFile output(path);
  std::ofstream file(output.temporaryPath());
  file << report.dump(2) << "\n";
  file.close();
  if (!file) throw std::runtime_error(fmt::format("{}: cannot write the report", path));
  output.commit();
}

namespace {
bool samePath(const std::string& a, const std::string& b) {
  if (a == "-" || b == "-" || a.empty() || b.empty()) return false;
  std::error_code error;
  if (std::filesystem::equivalent(a, b, error)) return true;
  return std::filesystem::weakly_canonical(a, error) == std::filesystem::weakly_canonical(b, error);
}
}  // namespace

void checkDistinct(const std::string& input, const std::string& output, const std::string& report) {
  if (samePath(input, output))
    throw std::runtime_error(fmt::format("{}: the output is the input; inputs are never modified", output));
  if (samePath(report, output) || samePath(report, input))
    throw std::runtime_error(fmt::format("{}: the report would overwrite a medium", report));
  if (report == "-" && output == "-")
    throw std::runtime_error("--report - and OUT - would both write to stdout");
}

void checkOutputs(const std::string& input, const std::string& output, const std::string& report) {
  checkDistinct(input, output, report);
  checkWritable(output);
  if (!report.empty() && report != "-") checkWritable(report);
}

std::uint64_t fileSize(const std::string& path) {
  std::error_code error;
  if (path == "-") return 0;
  const auto size = std::filesystem::file_size(path, error);
  return error ? 0 : size;
}

nlohmann::json summaryJson(const MediumSummary& summary, const std::string& path) {
  nlohmann::json grids = nlohmann::json::array();
  for (const auto& g : summary.grids)
    grids.push_back({{"name", g.name}, {"type", g.type}, {"active_voxels", g.active_voxels}, {"memory_bytes", g.memory_bytes}});
  return {{"path", path},
          {"active_voxels", summary.active_voxels},
          {"memory_bytes", summary.memory_bytes},
          {"file_bytes", fileSize(path)},
          {"voxel_size", summary.voxel_size},
          {"grids", grids}};
}

void SlabReading::addFlags(CLI::App& app) {
  app.add_option("--memory", memory_gb,
                 "GB: memory budget of reading in slabs (default: a quarter of the machine's memory, at most 4)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--in-core", in_core, "read the whole medium, not in slabs (the same result)");
}

std::uint64_t SlabReading::budgetBytes() const {
  return memory_gb > 0 ? std::uint64_t(memory_gb * 1e9) : defaultMemoryBudget();
}

void SlabReading::report(const std::string& tool, const std::string& input, bool in_slabs, const std::string& why_not,
                         const std::vector<std::string>& notes, bool verbose) const {
  if (!in_slabs) {
    if (verbose) fmt::print(stderr, "{}: note: {} is read whole: {}\n", tool, input, why_not);
    return;
  }
  for (const std::string& note : notes) fmt::print(stderr, "{}: note: {}\n", tool, note);
}

}  // namespace vdbappear::tool
