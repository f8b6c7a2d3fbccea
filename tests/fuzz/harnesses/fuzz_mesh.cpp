// libFuzzer harness: meshes (vdb_render --mesh, scene "meshes") through assimp, as OBJ files.
// Assimp is not instrumented: coverage guidance sees only this tree's side of the reader.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/render/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vdbappear::fuzz::readInputFile(data, size, "mesh.obj", [](const std::string& path) { vdbappear::readMesh(path); });
}
