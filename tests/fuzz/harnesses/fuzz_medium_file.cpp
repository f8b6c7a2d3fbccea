// libFuzzer harness: the medium reader on a VDB file (readMedium, every tool's input).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/medium_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "medium.vdb", [](const std::string& path) { vdbappear::readMedium(path); });
}
