// libFuzzer harness: tabulated phase functions (vdb_similarity --table), JSON or text.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/phase_table_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "phase.txt");
  try {
    vdbappear::readPhaseTableFile(path);
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
