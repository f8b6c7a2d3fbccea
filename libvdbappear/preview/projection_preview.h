#pragma once
// A quick look at a medium without a path tracer: an orthographic view of the medium that absorbs
// and emits its albedo, plus its own light where it has an `emission` grid (docs/medium.md §3b), shaded by a short shadow march toward a light (local occlusion only, no
// multiple scattering). For pictures and sanity checks, never for measurements: vdb_render is the
// instrument.

#include "libvdbappear/image/rgb_image.h"
#include "libvdbappear/math/vector.h"

namespace vdbappear {

struct Medium;
class ProgressBar;

struct PreviewOptions {
  int width = 512;                               // pixels; the height follows the framed box
  Vec3 view = Vec3(-0.55, 0.65, -0.55);          // direction the camera looks along
  Vec3 light = Vec3(-0.4, 0.3, -0.87);           // direction the light travels
  double shadow_voxels = 12;                     // length of the shadow march, in voxels
  double ambient = 0.3;                          // share of the light that ignores shadows
  Vec3 background = Vec3::Constant(0.18);
};

RgbImage renderPreview(const Medium& medium, const PreviewOptions& options, ProgressBar* progress = nullptr);

}  // namespace vdbappear
