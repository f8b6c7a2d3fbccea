// libFuzzer harness: tabulated phase functions (vdb_similarity --table), JSON or text.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/phase_table_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "phase.txt", [](const std::string& path) { vdbappear::readPhaseTableFile(path); });
}
