// libFuzzer harness: scene files (vdb_render --scene): reading, then building the lights, the
// ground and the camera without a medium. Paths in the file are not followed (no medium, no
// meshes, environment maps refused), so that the harness reads nothing but its input.
#include "fuzz/harnesses/fuzz_input.h"
#include "libvdbappear/render/render_scene.h"
#include "libvdbappear/render/scene_description.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vdbappear;
  const std::string path = fuzz::writeInput(data, size, "scene.json");
  SceneDescription scene;
  try {
    scene = readSceneFile(path);
  } catch (const std::exception& e) {
    fuzz::expectNamed(e, path);
    return 0;
  }
  scene.medium.clear();
  scene.meshes.clear();
  const ImageReader no_images = [](const std::string& file) -> RgbImage {
    throw std::runtime_error(file + ": not read by the fuzz harness");
  };
  try {
    buildRenderScene(scene, nullptr, no_images);
    sceneAreaLights(scene);
    cameraOf(scene, nullptr);
  } catch (const std::exception&) {  // errors of lights[K] name the light; the tool adds the file
  }
  return 0;
}
