// vdb_make_height_map and vdb_displacement_prefilter from the command line: a procedural map,
// prefiltered and rendered through the tools; the same files for any thread count; bad input gets
// one error line and writes nothing.
#include "libvdbappear/image/image_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/temp_dir.h"
#include "support/uv_meshes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace vdbappear {
namespace {

using test::exists;
using test::kMakeMap;
using test::kPrefilter;
using test::kRender;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

// Rates small enough for a test: 8 x 8 coarse cells, 64 paths per estimate, S of 5^4 bins.
const std::string kQuick = " -f 4 --paths 64 --angular-resolution 5 --pairs 50 --positions 4";

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(DisplacementCli, HelpShowsExamples) {
  for (const std::string& tool : {kMakeMap, kPrefilter}) {
    const auto r = runCommand(tool + " --help");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("Examples:"), std::string::npos) << tool;
  }
  const auto list = runCommand(kMakeMap + " --list");
  for (const char* kind : {"woven", "noise", "relief", "bumps"}) EXPECT_NE(list.out.find(kind), std::string::npos) << kind;
}

// A noise map of 32^2 cells, prefiltered at factor 4 on one thread and on two (the same four
// images), then rendered from its manifest.
TEST(DisplacementCli, MapPrefilteredAndRenderedThroughTheTools) {
  const TempDir dir;
  const std::string map = dir.path("noise.exr");
  ASSERT_EQ(runCommand(kMakeMap + " noise --cells 32 -o " + quote(map)).status, 0);
  const std::string brdf = R"( --brdf '{"distribution": "beckmann", "roughness": 0.2, "diffuse": 0.5}')";
  const auto one = runCommand(kPrefilter + " " + quote(map) + " " + quote(dir.path("one.json")) + kQuick + brdf +
                              " -j 1 --report " + quote(dir.path("report.json")));
  ASSERT_EQ(one.status, 0) << one.err;
  ASSERT_EQ(runCommand(kPrefilter + " " + quote(map) + " " + quote(dir.path("two.json")) + kQuick + brdf + " -j 2").status, 0);
  for (const char* part : {"height", "lobes", "T", "S"}) {
    const std::string a = dir.path(std::string("one.") + part + ".exr"), b = dir.path(std::string("two.") + part + ".exr");
    ASSERT_TRUE(exists(a)) << part;
    EXPECT_EQ(contents(a), contents(b)) << part << ": differs between 1 and 2 threads";
  }
  const auto report = nlohmann::json::parse(contents(dir.path("report.json")));
  EXPECT_EQ(report["bytes"]["height"].get<int>(), 4 * 9 * 9);  // (32 / 4 + 1)^2 floats
  EXPECT_EQ(report["bytes"]["S"].get<int>(), 4 * 3 * 625);
  const auto manifest = nlohmann::json::parse(contents(dir.path("one.json")));
  EXPECT_EQ(manifest["brdf"]["distribution"], "beckmann");
  EXPECT_EQ(manifest["cells"], nlohmann::json::array({8, 8}));

  std::ofstream(dir.path("scene.json")) << R"({"resolution": [24, 16], "spp": 4,
    "camera": {"position": [0.5, -1.5, 1.2], "target": [0.5, 0.5, 0], "up": [0, 0, 1], "fov": 40},
    "lights": [{"type": "sun", "direction": [0.3, 0.4, -1], "strength": 2}],
    "height_fields": [{"prefiltered": "one.json", "tiles": [2, 1]}]})";
  const auto render = runCommand(kRender + " --scene " + quote(dir.path("scene.json")) + " -o " + quote(dir.path("r.exr")));
  ASSERT_EQ(render.status, 0) << render.err;
  const RgbImage image = readRgbImage(dir.path("r.exr"));
  double sum = 0;
  for (float v : image.pixels) sum += v;
  EXPECT_GT(sum, 0);

  // With the relief term (docs/displacement.md §6): B beside S, its radius in the manifest, and
  // vdb_render shading with it.
  ASSERT_EQ(runCommand(kPrefilter + " " + quote(map) + " " + quote(dir.path("relief.json")) + kQuick + brdf +
                       " --relief-radius 1 --report " + quote(dir.path("relief_report.json"))).status, 0);
  EXPECT_TRUE(exists(dir.path("relief.B.exr")));
  EXPECT_EQ(nlohmann::json::parse(contents(dir.path("relief.json")))["relief_radius"], 1);
  EXPECT_EQ(nlohmann::json::parse(contents(dir.path("relief_report.json")))["bytes"]["B"].get<int>(), 4 * 3 * 625);
  std::string relief_scene = contents(dir.path("scene.json"));
  relief_scene.replace(relief_scene.find("one.json"), 8, "relief.json");
  std::ofstream(dir.path("relief_scene.json")) << relief_scene;
  const auto relief_render = runCommand(kRender + " --scene " + quote(dir.path("relief_scene.json")) + " -o " + quote(dir.path("rr.exr")));
  ASSERT_EQ(relief_render.status, 0) << relief_render.err;
  double relief_sum = 0;
  for (float v : readRgbImage(dir.path("rr.exr")).pixels) relief_sum += v;
  EXPECT_GT(relief_sum, 0);

  // Over a mesh by its UVs (a UV sphere; surface/mesh_shell.h). A mesh without UVs is refused,
  // naming it, and nothing is written.
  test::writeObj(dir.path("ball.obj"), test::uvSphere(Vec3(0.5, 0.5, 0), 0.4, 32, 16));
  test::writeObj(dir.path("plain.obj"), test::uvSphere(Vec3(0.5, 0.5, 0), 0.4, 32, 16), false);
  for (const std::string mesh : {"ball", "plain"}) {
    std::ofstream(dir.path(mesh + ".json")) << R"({"resolution": [24, 16], "spp": 4,
      "camera": {"position": [0.5, -1.5, 1.2], "target": [0.5, 0.5, 0], "up": [0, 0, 1], "fov": 40},
      "lights": [{"type": "sun", "direction": [0.3, 0.4, -1], "strength": 2}],
      "height_fields": [{"prefiltered": "one.json", "mesh": ")" + mesh + R"(.obj", "tiles": [4, 2]}]})";
    const std::string out = dir.path(mesh + ".exr");
    const auto over_mesh = runCommand(kRender + " --scene " + quote(dir.path(mesh + ".json")) + " -o " + quote(out));
    if (mesh == "ball") {
      ASSERT_EQ(over_mesh.status, 0) << over_mesh.err;
      // The map was prefiltered 1 wide; 4 x 2 tiles over a sphere of radius 0.4 span sqrt(area / 8) =
      // 0.516 (the facets' area over the UV area that Assimp keeps: not the poles' degenerate halves).
      EXPECT_NE(over_mesh.err.find("vdb_render: warning: " + dir.path("one.json") + ": a tile spans 0.516"), std::string::npos)
          << over_mesh.err;
      EXPECT_EQ(lineCount(over_mesh.err), 1) << over_mesh.err;
      double ball_sum = 0;
      for (float v : readRgbImage(out).pixels) ball_sum += v;
      EXPECT_GT(ball_sum, 0);
      continue;
    }
    EXPECT_NE(over_mesh.status, 0);
    EXPECT_EQ(lineCount(over_mesh.err), 1) << over_mesh.err;
    EXPECT_NE(over_mesh.err.find("plain.obj: the mesh has no texture coordinates (UVs)"), std::string::npos) << over_mesh.err;
    EXPECT_FALSE(exists(out));
  }

  // The manifest's keys are not the scene's to override.
  std::ofstream(dir.path("bad_scene.json")) << R"({"height_fields": [{"prefiltered": "one.json", "size": 2}]})";
  const auto refused = runCommand(kRender + " --scene " + quote(dir.path("bad_scene.json")) + " -o " + quote(dir.path("bad.exr")));
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.err.find("height_fields[0].size: not with \"prefiltered\""), std::string::npos) << refused.err;
  EXPECT_FALSE(exists(dir.path("bad.exr")));

  // A mipmap of the original and its models at factors 4 and 8 (§4.7.2); listed coarsest first it
  // is refused, naming the level, and writes nothing.
  std::string quick_at_8 = kQuick;
  quick_at_8.replace(quick_at_8.find("-f 4"), 4, "-f 8");
  // The coarser level's tables made over the map as a tile among its copies (the map tiles
  // seamlessly), which the manifest records.
  ASSERT_EQ(runCommand(kPrefilter + " " + quote(map) + " " + quote(dir.path("eight.json")) + quick_at_8 + brdf + " --periodic").status, 0);
  EXPECT_EQ(nlohmann::json::parse(contents(dir.path("eight.json")))["settings"]["edges"], "periodic");
  EXPECT_EQ(manifest["settings"]["edges"], "open");
  std::ofstream(dir.path("mipmap.json")) << R"({"resolution": [24, 16], "spp": 4,
    "camera": {"position": [0.5, -1.5, 1.2], "target": [0.5, 0.5, 0], "up": [0, 0, 1], "fov": 40},
    "lights": [{"type": "sun", "direction": [0.3, 0.4, -1], "strength": 2}],
    "height_fields": [{"file": "noise.exr", "mipmap": ["one.json", "eight.json"], "tiles": [2, 1]}]})";
  const auto mipmap = runCommand(kRender + " --scene " + quote(dir.path("mipmap.json")) + " -o " + quote(dir.path("m.exr")));
  ASSERT_EQ(mipmap.status, 0) << mipmap.err;
  EXPECT_TRUE(exists(dir.path("m.exr")));
  std::ofstream(dir.path("reversed.json")) << R"({"camera": {"position": [0.5, -1.5, 1.2], "target": [0.5, 0.5, 0]},
    "height_fields": [{"mipmap": ["eight.json", "one.json"]}]})";
  const auto reversed = runCommand(kRender + " --scene " + quote(dir.path("reversed.json")) + " -o " + quote(dir.path("bad.exr")));
  EXPECT_NE(reversed.status, 0);
  EXPECT_EQ(lineCount(reversed.err), 1) << reversed.err;
  EXPECT_NE(reversed.err.find("one.json: factor 4 after factor 8"), std::string::npos) << reversed.err;
  EXPECT_FALSE(exists(dir.path("bad.exr")));
}

// flag_parser: CLI11's refusals add "Run with --help for more information."
void expectRefused(const TempDir& dir, const std::string& command, const std::string& names, bool flag_parser = false) {
  const auto r = runCommand(command);
  EXPECT_NE(r.status, 0) << command;
  EXPECT_EQ(lineCount(r.err), flag_parser ? 2 : 1) << command << "\n" << r.err;
  EXPECT_NE(r.err.find(names), std::string::npos) << "expected '" << names << "' in: " << r.err;
  for (const char* file : {"out.json", "out.height.exr", "out.lobes.exr", "out.T.exr", "out.S.exr"})
    EXPECT_FALSE(exists(dir.path(file))) << command << " wrote " << file;
}

TEST(DisplacementCli, BadInputIsRefusedAndWritesNothing) {
  const TempDir dir;
  const std::string map = dir.path("map.exr"), out = quote(dir.path("out.json"));
  ASSERT_EQ(runCommand(kMakeMap + " relief --cells 30 -o " + quote(map)).status, 0);
  // A height that is not a number, named by its pixel.
  ImageChannels nan_map = readImageChannels(map);
  nan_map.values[5 * nan_map.width + 7] = std::nanf("");
  writeExr(nan_map, dir.path("nan.exr"));
  expectRefused(dir, kPrefilter + " " + quote(dir.path("nan.exr")) + " " + out + kQuick, "nan.exr");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + " -f 8", "the factor 8 does not divide the map's 30 x 30 cells");
  // --periodic on a map whose opposite edges differ, named with the vertex (the image's row 5 from
  // the top is the map's vertex row 25 of 30).
  ImageChannels stepped = readImageChannels(map);
  stepped.values[5 * stepped.width] += 1.0f;
  writeExr(stepped, dir.path("stepped.exr"));
  expectRefused(dir, kPrefilter + " " + quote(dir.path("stepped.exr")) + " " + out + " -f 5 --periodic",
                "stepped.exr (--periodic): the map does not tile seamlessly: vertex (0, 25)");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + R"( --brdf '{"roughness": -0.1}')", "roughness");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + R"( --brdf '{"colour": 1}')", "colour");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + R"( --brdf '{"roughness": 0.1')", "--brdf: not a JSON object");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + " --stretch 0.5,x", "--stretch: 'x' is not SX or SX:SY");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + " --stretch 0:1", "both scales must be positive");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + " --view-horizon 95", "--view-horizon", true);
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + kQuick + " --base-curvature -1", "--base-curvature", true);
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + " -f 5 --paths 16 --pairs 5 --relief-radius 3",
                "the relief's radius must be 0 (none) or span at most the coarse map's 6 cells");
  expectRefused(dir, kPrefilter + " " + quote(dir.path("missing.exr")) + " " + out, "missing.exr");
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + quote(dir.path("out.exr")), "OUT must end in .json", true);
  expectRefused(dir, kPrefilter + " " + quote(map) + " " + out + " --factor 1", "--factor", true);
  const auto unknown = runCommand(kMakeMap + " marble -o " + quote(dir.path("m.exr")));
  EXPECT_NE(unknown.status, 0);
  EXPECT_NE(unknown.err.find("unknown height map 'marble'"), std::string::npos) << unknown.err;
  EXPECT_FALSE(exists(dir.path("m.exr")));
}

}  // namespace
}  // namespace vdbappear
