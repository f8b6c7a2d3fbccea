#include "libvdbappear/cluster/mpi_process_group.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace vdbappear {

namespace {

void check(int status, const char* call) {
  if (status == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(status, text, &length);
  throw std::runtime_error(std::string(call) + " failed: " + std::string(text, length));
}

// MPI counts are ints: large buffers go in pieces of at most 2^30 elements.
template <typename T>
void allreduceSum(T* values, std::size_t n, MPI_Datatype type) {
  constexpr std::size_t kPiece = std::size_t(1) << 30;
  for (std::size_t first = 0; first < n; first += kPiece) {
    const int count = int(std::min(kPiece, n - first));
    check(MPI_Allreduce(MPI_IN_PLACE, values + first, count, type, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
  }
}

class MpiWorkCounter final : public WorkCounter {
 public:
  explicit MpiWorkCounter(int rank) {
    const MPI_Aint bytes = rank == 0 ? sizeof(std::uint64_t) : 0;
    check(MPI_Win_allocate(bytes, sizeof(std::uint64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &next_, &window_),
          "MPI_Win_allocate");
    if (rank == 0) {
      MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window_);
      *next_ = 0;
      MPI_Win_unlock(0, window_);
    }
    check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
    check(MPI_Win_lock_all(MPI_MODE_NOCHECK, window_), "MPI_Win_lock_all");
  }
  ~MpiWorkCounter() override {
    MPI_Win_unlock_all(window_);
    MPI_Win_free(&window_);
  }
  MpiWorkCounter(const MpiWorkCounter&) = delete;
  MpiWorkCounter& operator=(const MpiWorkCounter&) = delete;

  std::uint64_t claim(std::uint64_t n) override {
    std::uint64_t first = 0;
    check(MPI_Fetch_and_op(&n, &first, MPI_UINT64_T, 0, 0, MPI_SUM, window_), "MPI_Fetch_and_op");
    check(MPI_Win_flush(0, window_), "MPI_Win_flush");
    return first;
  }

 private:
  MPI_Win window_ = MPI_WIN_NULL;
  std::uint64_t* next_ = nullptr;
};

}  // namespace

MpiProcessGroup::MpiProcessGroup(int* argc, char*** argv) {
  int provided = 0;
  check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  // Errors come back as status codes (check() makes them exceptions) instead of ending the job.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (provided < MPI_THREAD_FUNNELED) {
    if (rank_ == 0) std::fprintf(stderr, "error: the MPI library gives no MPI_THREAD_FUNNELED support\n");
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
}

MpiProcessGroup::~MpiProcessGroup() { MPI_Finalize(); }

std::unique_ptr<WorkCounter> MpiProcessGroup::workCounter(std::uint64_t) const {
  return std::make_unique<MpiWorkCounter>(rank_);
}

void MpiProcessGroup::sum(double* values, std::size_t n) const { allreduceSum(values, n, MPI_DOUBLE); }
void MpiProcessGroup::sum(std::uint64_t* values, std::size_t n) const { allreduceSum(values, n, MPI_UINT64_T); }
void MpiProcessGroup::sum(std::uint32_t* values, std::size_t n) const { allreduceSum(values, n, MPI_UINT32_T); }

void MpiProcessGroup::broadcast(std::int64_t* values, std::size_t n) const {
  check(MPI_Bcast(values, int(n), MPI_INT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast");
}

int MpiProcessGroup::firstFailingRank(bool failed) const {
  int candidate = failed ? rank_ : size_, first = size_;
  check(MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
  return first < size_ ? first : -1;
}

void MpiProcessGroup::abortJob(int status) const { MPI_Abort(MPI_COMM_WORLD, status); }

}  // namespace vdbappear
