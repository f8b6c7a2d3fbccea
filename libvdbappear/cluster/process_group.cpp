#include "libvdbappear/cluster/process_group.h"

#include <atomic>
#include <cstdlib>
#include <exception>

namespace vdbappear {

namespace {

class SoloWorkCounter final : public WorkCounter {
 public:
  std::uint64_t claim(std::uint64_t n) override { return next_.fetch_add(n); }

 private:
  std::atomic<std::uint64_t> next_{0};
};

}  // namespace

void ProcessGroup::together(const std::function<void()>& step) const {
  std::exception_ptr error;
  std::string message;
  try {
    step();
  } catch (const std::exception& e) {
    error = std::current_exception();
    message = e.what();
  }
  const int first = firstFailingRank(bool(error));
  if (first < 0) return;
  if (!isShared()) std::rethrow_exception(error);
  throw GroupFailure(first == rank() ? message : std::string());
}

std::unique_ptr<WorkCounter> SoloProcessGroup::workCounter(std::uint64_t) const {
  return std::make_unique<SoloWorkCounter>();
}

void SoloProcessGroup::abortJob(int status) const { std::exit(status); }

bool startedByMpiLauncher() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(variable)) return true;
  return false;
}

}  // namespace vdbappear
