// libFuzzer harness: the medium reader on a VDB stream (readMediumStream: what `-` reads from stdin).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/medium_file.h"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    vdbappear::readMediumStream(in, "fuzz-stream");
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, "fuzz-stream");
  }
  return 0;
}
