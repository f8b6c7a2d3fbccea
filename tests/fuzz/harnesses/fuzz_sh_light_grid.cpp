// libFuzzer harness: SH light grids (vdb_render --sh-lightgrid), VDB files.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/sh_light_grid_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "lightgrid.vdb", [](const std::string& path) { vdbappear::readShLightGrid(path); });
}
