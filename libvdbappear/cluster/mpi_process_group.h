#pragma once
// The ranks of MPI_COMM_WORLD as a ProcessGroup (cluster/process_group.h). Only the tools link it
// (library vdbappear_cluster); the MPI header stays in the .cpp.

#include "libvdbappear/cluster/process_group.h"

namespace vdbappear {

class MpiProcessGroup final : public ProcessGroup {
 public:
  // MPI_Init_thread with MPI_THREAD_FUNNELED: only the thread that made the group calls MPI (TBB's
  // workers never do).
  MpiProcessGroup(int* argc, char*** argv);
  ~MpiProcessGroup() override;  // MPI_Finalize
  MpiProcessGroup(const MpiProcessGroup&) = delete;
  MpiProcessGroup& operator=(const MpiProcessGroup&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // One 64-bit integer on rank 0 in an MPI window, advanced with MPI_Fetch_and_op under a passive
  // lock_all epoch: no rank has to serve the others' requests.
  std::unique_ptr<WorkCounter> workCounter(std::uint64_t count) const override;
  void sum(double* values, std::size_t n) const override;
  void sum(std::uint64_t* values, std::size_t n) const override;
  void sum(std::uint32_t* values, std::size_t n) const override;
  void broadcast(std::int64_t* values, std::size_t n) const override;
  int firstFailingRank(bool failed) const override;
  void abortJob(int status) const override;  // MPI_Abort

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace vdbappear
