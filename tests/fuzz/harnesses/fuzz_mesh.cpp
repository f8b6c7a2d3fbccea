// libFuzzer harness: meshes (vdb_render --mesh, scene "meshes") through assimp, as OBJ files.
// Assimp is not instrumented: coverage guidance sees only this tree's side of the reader.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/render/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdbappear::fuzz::writeInput(data, size, "mesh.obj");
  try {
    vdbappear::readMesh(path);
  } catch (const std::exception& e) {
    vdbappear::fuzz::expectNamed(e, path);
  }
  return 0;
}
