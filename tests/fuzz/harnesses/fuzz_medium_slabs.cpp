// libFuzzer harness: the slab reader on a VDB file (vdb_sggx_downsample's input, read in parts:
// io/mapped_vdb_file.h, io/slab_tree_index.h), downsampled at F = 2 in as many slabs as the smallest
// budget it accepts allows, its output spilled beside the input.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/downsample/streamed_downsample.h"
#include "libvdbappear/io/medium_slabs.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "medium.vdb", [](const std::string& path) {
    const vdbappear::MediumSlabs::Plan plan = vdbappear::MediumSlabs(path, {}).plan(16, ~std::uint64_t(0));
    vdbappear::downsampleNaiveStreamed(path, {}, {2, vdbappear::SggxWeighting::Count},
                                       plan.resident_bytes + plan.largest_cell_bytes, nullptr, nullptr, path + ".out.vdb");
  });
}
