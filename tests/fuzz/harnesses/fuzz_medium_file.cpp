// libFuzzer harness: the medium reader on a VDB file (readMedium, every tool's input).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/medium_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "medium.vdb");
  try {
    vdbappear::readMedium(path);
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
