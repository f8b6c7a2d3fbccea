// libFuzzer harness: light lists (vdb_sh_lightgrid --lights).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/light_list_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "lights.json");
  try {
    vdbappear::readLightList(path);
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
