#pragma once
// The processes that share one job: the ranks of an MPI job started by mpirun or srun
// (cluster/mpi_process_group.cpp, built when CMake finds MPI), or this process alone. The library's
// distributed work (render/render_image.cpp) splits by a group and never names MPI; docs/scaling.md
// says what is split and what is replicated. Light header.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace vdbappear {

// Hands out the items [0, count) across a group, first come, first served: dynamic load balancing
// without a master process.
class WorkCounter {
 public:
  virtual ~WorkCounter() = default;
  // Claims up to n further items for this process: returns the first, `first` to min(first + n,
  // count) are this process's; count or more when none is left. Any thread may not call it: only
  // the thread that created the counter.
  virtual std::uint64_t claim(std::uint64_t n) = 0;
};

// Thrown on every process by ProcessGroup::together when a step failed on one of them. The lowest
// failing rank carries its own error's message, the others an empty one: the job reports the
// failure once.
class GroupFailure : public std::runtime_error {
 public:
  explicit GroupFailure(const std::string& message) : std::runtime_error(message) {}
};

class ProcessGroup {
 public:
  virtual ~ProcessGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool isRoot() const { return rank() == 0; }
  bool isShared() const { return size() > 1; }

  // Collective (every process calls these, in the same order):
  // a counter over [0, count), shared by the group while the returned object lives (destroyed
  // collectively too);
  virtual std::unique_ptr<WorkCounter> workCounter(std::uint64_t count) const = 0;
  // element-wise sums over the group, left on every process (in place);
  virtual void sum(double* values, std::size_t n) const = 0;
  virtual void sum(std::uint64_t* values, std::size_t n) const = 0;
  virtual void sum(std::uint32_t* values, std::size_t n) const = 0;
  // the root's values on every process;
  virtual void broadcast(std::int64_t* values, std::size_t n) const = 0;
  // the lowest rank for which `failed` holds, or -1 when it holds for none.
  virtual int firstFailingRank(bool failed) const = 0;

  // Collective: runs `step` on every process; when it throws on any of them, throws GroupFailure
  // on all (see there), so that no process waits for one that has given up.
  void together(const std::function<void()>& step) const;

  // Ends the whole job now, every process, with `status`: for an error after which the others
  // cannot go on (one that is not agreed through together()).
  virtual void abortJob(int status) const = 0;
};

// This process alone: every collective is the identity.
class SoloProcessGroup final : public ProcessGroup {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::unique_ptr<WorkCounter> workCounter(std::uint64_t count) const override;
  void sum(double*, std::size_t) const override {}
  void sum(std::uint64_t*, std::size_t) const override {}
  void sum(std::uint32_t*, std::size_t) const override {}
  void broadcast(std::int64_t*, std::size_t) const override {}
  int firstFailingRank(bool failed) const override { return failed ? 0 : -1; }
  void abortJob(int status) const override;
};

// The group of this process: the ranks of its MPI job when the build has MPI and the process was
// started by mpirun or srun (MPI is initialised here and finalised when the group is destroyed),
// this process alone otherwise. Call it once, first thing in main.
std::unique_ptr<ProcessGroup> joinProcessGroup(int* argc, char*** argv);

// Whether the environment says this process is one rank of a job started by an MPI launcher
// (Open MPI's mpirun, Slurm's srun through PMI or PMIx).
bool startedByMpiLauncher();

}  // namespace vdbappear
