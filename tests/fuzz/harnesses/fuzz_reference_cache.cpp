// libFuzzer harness: the reference-image cache of vdb_optimize_weights (optimize/reference_cache.h).
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/optimize/reference_cache.h"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "key.ref");
  const vdbappear::ReferenceCache cache(std::filesystem::path(path).parent_path().string());
  try {
    cache.find("key");
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
