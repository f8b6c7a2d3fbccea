// libFuzzer harness: the reference-image cache of vdb_optimize_weights (optimize/reference_cache.h).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/optimize/reference_cache.h"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "key.ref", [](const std::string& path) {
    vdbappear::ReferenceCache(std::filesystem::path(path).parent_path().string()).find("key");
  });
}
