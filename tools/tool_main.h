#pragma once
// What every vdbappear tool shares: one error line and a non-zero exit on failure, a thread limit,
// and JSON reports written atomically.

#include "libvdbappear/util/progress.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {
class ProcessGroup;
struct MediumSummary;
struct GridMapping;
struct Medium;
}

namespace vdbappear::tool {

// Parses flags, then runs `body`, which returns the exit status. A flag error prints CLI11's
// message and exits non-zero; any exception thrown by `body` becomes one line
// "TOOL: error: MESSAGE" on stderr and exit status 1.
int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

// run() for a tool whose work the ranks of `group` share (cluster/process_group.h). Only the root
// prints help and flag errors. An error the group agreed on (GroupFailure) is printed once, by the
// rank it happened on, and every rank exits 1; any other error on one rank of several ends the whole
// job (ProcessGroup::abortJob), since the others would wait for it forever.
int run(CLI::App& app, int argc, char** argv, const ProcessGroup& group, const std::function<int()>& body);

// Adds -j/--threads N (0: all cores). The limit holds while the returned object lives.
class ThreadLimit {
 public:
  explicit ThreadLimit(CLI::App& app);
  ~ThreadLimit();
  void apply();

 private:
  int threads_ = 0;
  std::shared_ptr<void> control_;
};

// Adds --grid ROLE=GRID[,GRID,GRID][/DIVISOR][:SCALE], repeatable: the file's foreign grids read
// as the medium's (io/grid_mapping.h), into `mapping`; a malformed rule or a role given twice is a
// flag error. And --from auto|blender|houdini|none: the preset for the roles the rules leave.
void addGridMapping(CLI::App& app, GridMapping& mapping);

// readMedium, then the reader's notes (what a preset mapped) on stderr as "TOOL: note: ...".
std::shared_ptr<Medium> readInputMedium(const std::string& tool, const std::string& path, const GridMapping& mapping);

// Writes `report` as indented JSON to `path` ("-": stdout), through a temporary file.
void writeJsonReport(const std::string& path, const nlohmann::json& report);

std::uint64_t fileSize(const std::string& path);  // 0 for "-" or a missing file

// A medium file for a report: path, active voxels, bytes in memory and on disk, voxel size, grids.
nlohmann::json summaryJson(const MediumSummary& summary, const std::string& path);

// Refuses an output that would overwrite the input (inputs are never modified) or another output.
void checkDistinct(const std::string& input, const std::string& output, const std::string& report);

// Before any work: checkDistinct, then that OUT and the report (unless empty or "-") can be written
// (checkWritable).
void checkOutputs(const std::string& input, const std::string& output, const std::string& report);

// Reading a medium file in slabs within a memory budget (docs/scaling.md §5): the flags --memory and
// --in-core, and what the tool says about it.
struct SlabReading {
  double memory_gb = 0;  // 0: defaultMemoryBudget()
  bool in_core = false;

  void addFlags(CLI::App& app);
  bool appliesTo(const std::string& input) const { return !in_core && input != "-"; }  // stdin is read whole
  std::uint64_t budgetBytes() const;

  // read(budget_bytes, &why_not, &progress), a library reduction in slabs that returns an optional
  // result with the reader's notes, behind a progress bar labelled `label`; nullopt without calling
  // it where the file is read whole (--in-core, stdin). Prints the notes, or with -v why the file was
  // read whole.
  template <typename Read>
  auto run(const std::string& tool, const std::string& input, const char* label, bool verbose, const Read& read) const
      -> decltype(read(std::uint64_t(0), static_cast<std::string*>(nullptr), static_cast<ProgressBar*>(nullptr))) {
    if (!appliesTo(input)) return std::nullopt;
    std::string why_not;
    decltype(read(std::uint64_t(0), &why_not, static_cast<ProgressBar*>(nullptr))) result;
    {
      ProgressBar progress(label, 0);
      result = read(budgetBytes(), &why_not, &progress);
    }
    report(tool, input, bool(result), why_not, result ? result->notes : std::vector<std::string>{}, verbose);
    return result;
  }

 private:
  void report(const std::string& tool, const std::string& input, bool in_slabs, const std::string& why_not,
              const std::vector<std::string>& notes, bool verbose) const;
};

}  // namespace vdbappear::tool
