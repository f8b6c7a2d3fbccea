// vdb_preview: a quick picture of a medium (absorption-emission with local shadows), as PNG or EXR.
#include "tool_main.h"

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/preview/projection_preview.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_preview";

constexpr const char* kExamples = R"(Examples:
  vdb_preview twill.vdb -o twill.png
  vdb_preview cloud.vdb -o cloud.png --width 800 --view 0,1,-0.3
  vdb_make_medium velvet -o - | vdb_preview - -o velvet.png
Not a renderer: no multiple scattering, no phase functions, shadows only over --shadow voxels.
Use vdb_render for pictures that mean something.)";

Vec3 toVec3(const std::vector<double>& v) { return Vec3(v[0], v[1], v[2]); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Draws a quick orthographic preview of a medium: it absorbs and glows with its albedo, shaded "
               "by short shadow rays.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  std::string input, output;
  PreviewOptions options;
  std::vector<double> view{options.view.x(), options.view.y(), options.view.z()};
  std::vector<double> light{options.light.x(), options.light.y(), options.light.z()};
  app.add_option("MEDIUM", input, "input medium (.vdb); - reads a VDB stream from stdin")->required();
  app.add_option("-o,--output", output, "output image: .png (sRGB) or .exr (linear)")->required();
  app.add_option("--width", options.width, "image width in pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--view", view, "direction the camera looks along X,Y,Z")->delimiter(',')->expected(3)
      ->capture_default_str();
  app.add_option("--light", light, "direction the light travels X,Y,Z")->delimiter(',')->expected(3)
      ->capture_default_str();
  app.add_option("--shadow", options.shadow_voxels, "shadow march length in voxels (0: no shadows)")
      ->check(CLI::Range(0.0, 1000.0))->capture_default_str();
  GridMapping mapping;
  tool::addGridMapping(app, mapping);
  tool::ThreadLimit threads(app);

  return tool::run(app, argc, argv, [&] {
    threads.apply();
    options.view = toVec3(view);
    options.light = toVec3(light);
    if (options.view.norm() == 0 || options.light.norm() == 0) throw std::runtime_error("--view and --light must be non-zero");
    tool::checkOutputs(input, output, "");
    const MediumPtr medium = tool::readInputMedium(kTool, input, mapping);
    ProgressBar progress("preview", 0);
    writeImage(renderPreview(*medium, options, &progress), output);
    return 0;
  });
}
