// vdb_make_height_map: procedural displacement maps (docs/displacement.md §7), the test surfaces of
// the displacement prefiltering, deterministic under --seed.
#include "tool_main.h"

#include "libvdbappear/image/height_map_file.h"
#include "libvdbappear/procedural/height_maps.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_make_height_map";

constexpr const char* kExamples = R"(Examples:
  vdb_make_height_map --list
  vdb_make_height_map woven -o twill.exr                 # 1025 x 1025 pixels, 1024^2 cells
  vdb_make_height_map noise --cells 256 --seed 7 -o noise.exr
  vdb_make_height_map relief -o relief.exr && vdb_displacement_prefilter relief.exr relief_8x.json -f 8
Heights are in units of the map's width (a scene's "size": 1, "height_scale": 1 keeps its shape);
every map tiles seamlessly.)";

constexpr const char* kDescriptions[] = {
    "a 4-harness twill from its yarns: 16 warp and 16 weft yarns rising over and dipping under each other",
    "a noise floor: 48 periodic sinusoids of 4 to 64 cycles per map, amplitudes as 1/f, RMS slope 0.6 (--seed)",
    "a relief: 8 x 8 raised squares with chamfered edges and engraved rings",
    "bumps: 8 x 8 round caps, one inside each lattice cell, radii and places by --seed (the chapter's ball)"};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Writes a procedural height map (an EXR of one channel) for vdb_displacement_prefilter and "
               "vdb_render's height fields.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  std::string kind, output;
  int cells = 1024;
  std::uint64_t seed = 1;
  bool list = false, verbose = false;
  app.add_option("KIND", kind, "kind of map (see --list)");
  app.add_option("-o,--output", output, "output height map (.exr)");
  app.add_flag("--list", list, "list the kinds and exit");
  app.add_option("--cells", cells, "cells per side; the image has one pixel more (woven: a multiple of 16)")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  app.add_option("--seed", seed, "random seed (noise, bumps)")->capture_default_str();
  app.add_flag("-v,--verbose", verbose, "print the map's height range and RMS slope to stderr");

  return tool::run(app, argc, argv, [&] {
    if (list) {
      for (std::size_t k = 0; k < heightMapNames().size(); ++k)
        fmt::print("{:8} {}\n", heightMapNames()[k], k < std::size(kDescriptions) ? kDescriptions[k] : "");
      return 0;
    }
    if (kind.empty()) throw std::runtime_error("no KIND given (see --list)");
    if (output.empty()) throw std::runtime_error("no output given (-o OUT.exr)");
    tool::checkOutputs("", output, "");
    const HeightField field = heightMapByName(kind, cells, seed);
    writeHeightMap(field, output);
    if (verbose) {
      const auto [lo, hi] = std::minmax_element(field.heights().begin(), field.heights().end());
      double slope = 0;
      for (int j = 0; j < field.cellsY(); ++j)
        for (int i = 0; i < field.cellsX(); ++i) slope += field.cellSlope(i, j).squaredNorm();
      fmt::print(stderr, "{}: {}: {} x {} cells, heights {:.4g} to {:.4g}, RMS slope {:.3f}\n", kTool, output,
                 field.cellsX(), field.cellsY(), *lo, *hi, std::sqrt(slope / (double(field.cellsX()) * field.cellsY())));
    }
    return 0;
  });
}
