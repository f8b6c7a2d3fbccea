// libFuzzer harness: SH light grids (vdb_render --sh-lightgrid), VDB files.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/io/sh_light_grid_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "lightgrid.vdb");
  try {
    vdbappear::readShLightGrid(path);
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
