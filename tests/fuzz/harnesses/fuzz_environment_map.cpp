// libFuzzer harness: environment maps (scene lights of type env_map) through OpenImageIO, as
// OpenEXR files. OpenImageIO and OpenEXR are not instrumented (OpenEXR is fuzzed by OSS-Fuzz).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/image/image_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "sky.exr", [](const std::string& path) { vdbappear::readRgbImage(path); });
}
