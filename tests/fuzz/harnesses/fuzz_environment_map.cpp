// libFuzzer harness: environment maps (scene lights of type env_map) as OpenEXR files, read
// through OpenEXR (OpenImageIO for other formats). Neither is instrumented (OpenEXR is fuzzed by
// OSS-Fuzz).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/image/image_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "sky.exr", [](const std::string& path) { vdbappear::readRgbImage(path); });
}
