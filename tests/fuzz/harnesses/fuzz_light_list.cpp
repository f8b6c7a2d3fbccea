// libFuzzer harness: light lists (vdb_sh_lightgrid --lights).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/light_list_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "lights.json", [](const std::string& path) { vdbappear::readLightList(path); });
}
