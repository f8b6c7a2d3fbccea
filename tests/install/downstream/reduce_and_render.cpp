// Reads a medium, halves its resolution (Eq. 5-6 of the downsampling paper), writes it, and renders
// both under the default sky: the example program of docs/library.md.
#include <libvdbappear/downsample/naive_downsample.h>
#include <libvdbappear/io/medium_summary.h>
#include <libvdbappear/render/scene_description.h>

#include <cstdio>
#include <numeric>

using namespace vdbappear;

double meanPixel(const MediumPtr& medium) {
  SceneDescription scene;  // framed from +z, lit by a white sky
  scene.lights.push_back({{"type", "env"}, {"radiance", 1.0}});
  scene.render.width = scene.render.height = 32;
  const auto view = std::make_shared<MediumView>(medium, Interpolation::kNearest);
  const RenderScene render_scene = buildRenderScene(scene, view, nullptr);  // no environment map to read
  const RenderResult image = renderImage(render_scene, PinholeCamera(cameraOf(scene, view.get()), 32, 32), scene.render);
  return std::accumulate(image.mean.begin(), image.mean.end(), 0.0) / image.mean.size();
}

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: reduce_and_render IN.vdb OUT.vdb\n"), 2;
  const MediumPtr fine = readMedium(argv[1]);
  const MediumPtr coarse = downsampleNaive(*fine, DownsampleOptions{2}).medium;
  writeMedium(*coarse, argv[2], "reduce_and_render");
  std::printf("%llu -> %llu active voxels; mean pixel %.4f -> %.4f\n",
              (unsigned long long)summarize(*fine).active_voxels, (unsigned long long)summarize(*coarse).active_voxels,
              meanPixel(fine), meanPixel(coarse));
}
