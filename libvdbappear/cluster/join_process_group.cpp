// joinProcessGroup: the MPI job's ranks in a build with MPI (VDBAPPEAR_WITH_MPI, set by CMake when
// it finds MPI), this process alone otherwise. Compiled into the static library vdbappear_cluster,
// which only the tools that split their work link, so that libvdbappear itself never links MPI.
#include "libvdbappear/cluster/process_group.h"

#ifdef VDBAPPEAR_WITH_MPI
#include "libvdbappear/cluster/mpi_process_group.h"
#endif

namespace vdbappear {

std::unique_ptr<ProcessGroup> joinProcessGroup([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef VDBAPPEAR_WITH_MPI
  if (startedByMpiLauncher()) return std::make_unique<MpiProcessGroup>(argc, argv);
#endif
  return std::make_unique<SoloProcessGroup>();
}

}  // namespace vdbappear
