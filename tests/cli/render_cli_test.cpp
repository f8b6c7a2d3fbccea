// vdb_render from the command line: outputs and AOVs, determinism over threads, scene files and
// flag overrides, and one clear error (no output file) for each kind of bad input.
#include "libvdbappear/image/image_file.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/image_footprint.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using test::exists;
using test::kRender;
using test::lineCount;
using test::quote;
using test::runCommand;
using test::TempDir;

const std::string kCube = quote(std::string(GOLDEN_DIR) + "/cube8.vdb");

TEST(RenderCli, HelpHasExamples) {
  const auto help = runCommand(kRender + " --help");
  ASSERT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("Examples:"), std::string::npos);
  EXPECT_NE(help.out.find("--sh-light"), std::string::npos);
}

// The default lighting (defaultLights, issue 26) shows a white smoke: a density grid alone (albedo 1,
// as a smoke cache holds it) framed from the default +z stands out from the sky and has structure.
// Negative control: the old default, a white sky alone (the white furnace, now --env 1), hides it.
TEST(RenderCli, DefaultLightingShowsAWhiteSmoke) {
  const TempDir dir;
  const std::string cloud = dir.path("cloud.vdb"), smoke = dir.path("smoke.vdb");
  ASSERT_EQ(runCommand(quote(VDB_MAKE_MEDIUM) + " cloud --res 32 -o " + quote(cloud)).status, 0);
  test::writeRawVdb(smoke, {readMedium(cloud)->density->deepCopy()});
  const std::string lit = dir.path("lit.exr"), furnace = dir.path("furnace.exr");
  const std::string flags = " --res 64x48 --spp 32 --aov alpha";
  ASSERT_EQ(runCommand(kRender + " " + quote(smoke) + " -o " + quote(lit) + flags).status, 0);
  ASSERT_EQ(runCommand(kRender + " " + quote(smoke) + " -o " + quote(furnace) + flags + " --env 1").status, 0);
  const test::Footprint shown = test::footprintOf(lit), hidden = test::footprintOf(furnace);
  EXPECT_GT(shown.coverage, 0.05);
  EXPECT_GT(shown.contrast, 0.5);
  EXPECT_GT(shown.structure, 0.15);
  EXPECT_LT(hidden.contrast, 0.02);
  EXPECT_LT(hidden.structure, 0.05);
}

// An emitting medium (docs/medium.md §3b) glows with no light at all, and vdb_sggx_downsample
// carries its emission (no "dropped grid" warning): the uniform 8^3 cube at half resolution is the
// same cube, so it renders the same. Negative control: without its emission grid it is black.
TEST(RenderCli, AnEmittingMediumGlowsAndKeepsItsEmissionWhenDownsampled) {
  const TempDir dir;
  const MediumPtr cube = readMedium(std::string(GOLDEN_DIR) + "/cube8.vdb");
  auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*cube, grid_names::kEmission, openvdb::Vec3s(0.0f));
  emission->topologyUnion(*cube->density);
  for (auto v = emission->beginValueOn(); v; ++v) v.setValue(openvdb::Vec3s(2.0f, 1.0f, 0.5f));
  openvdb::GridPtrVec grids = test::copyGrids(*cube);
  test::writeRawVdb(dir.path("dark.vdb"), grids);
  grids.push_back(emission);
  test::writeRawVdb(dir.path("glow.vdb"), grids);
  const auto down = runCommand(quote(VDB_SGGX_DOWNSAMPLE) + " -f 2 " + quote(dir.path("glow.vdb")) + " " +
                               quote(dir.path("glow2.vdb")));
  ASSERT_EQ(down.status, 0) << down.err;
  EXPECT_EQ(down.err.find("dropped"), std::string::npos) << down.err;
  const auto mean = [&](const std::string& medium) {
    const std::string out = dir.path(medium + ".exr");
    const auto r = runCommand(kRender + " " + quote(dir.path(medium + ".vdb")) + " -o " + quote(out) +
                              " --res 16x16 --spp 64 --env 0");
    EXPECT_EQ(r.status, 0) << r.err;
    const ImageChannels image = readImageChannels(out);
    double sum = 0;
    for (int i = 0; i < image.width * image.height; ++i) sum += image.values[std::size_t(i) * image.names.size()];
    return sum / (image.width * image.height);
  };
  const double glow = mean("glow"), coarse = mean("glow2");
  EXPECT_GT(glow, 0.05);
  EXPECT_NEAR(coarse, glow, 0.05 * glow);
  EXPECT_EQ(mean("dark"), 0.0);
}

TEST(RenderCli, WritesExrWithAovsPreviewAndReport) {
  TempDir dir;
  const std::string out = dir.path("cube.exr"), png = dir.path("cube.png"), report = dir.path("r.json");
  const auto r = runCommand(kRender + " " + kCube + " -o " + quote(out) + " --preview " + quote(png) +
                            " --res 12x8 --spp 4 --view -x --sun 1,0,-1,2 --env 0.1 --ground --aov variance --report " +
                            quote(report));
  ASSERT_EQ(r.status, 0) << r.err;
  const ImageChannels image = readImageChannels(out);
  EXPECT_EQ(image.width, 12);
  EXPECT_EQ(image.height, 8);
  EXPECT_EQ(image.names, (std::vector<std::string>{"R", "G", "B", "variance.R", "variance.G", "variance.B"}));
  EXPECT_TRUE(exists(png));
  std::ifstream in(report);
  const auto json = nlohmann::json::parse(in);
  EXPECT_EQ(json["spp"], 4);
  EXPECT_EQ(json["majorant_violations"], 0);
  EXPECT_GT(json["paths_per_second"].get<double>(), 0);
}

// --aov time: per pixel, the seconds spent on its samples, non-negative and summing to no more
// than the render's seconds times its threads; the report's tiles cover the image in 8 x 8 tiles and
// sum to the channel's total. Negative control: the channel varies (the cube's pixels cost more
// than the empty ones around it).
TEST(RenderCli, TimeAovSaysWhereTheTimeWent) {
  TempDir dir;
  const std::string out = dir.path("t.exr"), report = dir.path("t.json");
  const auto r = runCommand(kRender + " " + kCube + " -o " + quote(out) + " --res 20x12 --spp 16 -j 1 --aov time --report " +
                            quote(report));
  ASSERT_EQ(r.status, 0) << r.err;
  const ImageChannels image = readImageChannels(out);
  ASSERT_EQ(image.names.back(), "time");
  const std::size_t n = image.names.size();
  double total = 0, least = 1e30, most = 0;
  for (std::size_t i = n - 1; i < image.values.size(); i += n) {
    EXPECT_GE(image.values[i], 0.0f);
    total += image.values[i];
    least = std::min(least, double(image.values[i]));
    most = std::max(most, double(image.values[i]));
  }
  std::ifstream in(report);
  const auto json = nlohmann::json::parse(in);
  EXPECT_LE(total, json["seconds"].get<double>() * 1.001);
  EXPECT_GT(most, 2 * least);
  const auto& tiles = json["tile_seconds"];
  EXPECT_EQ(tiles["tiles"], 3 * 2);  // ceil(20 / 8) x ceil(12 / 8)
  EXPECT_EQ(tiles["values"].size(), 6u);
  EXPECT_NEAR(tiles["total"].get<double>(), total, 1e-3 * total + 1e-9);
  EXPECT_LE(tiles["median"].get<double>(), tiles["max"].get<double>());
}

// An EXR render never loads OpenImageIO, whose 260 shared libraries cost every process that links
// it 0.4 s and 128 MB at start (docs/rendering.md §7); a PNG preview loads it, through the module
// that lies next to libvdbappear_image. The dynamic loader's own log says what it loaded.
TEST(RenderCli, OpenImageIOIsLoadedOnlyForFormatsOtherThanExr) {
  const TempDir dir;
  const std::string flags = " --res 8 --spp 1 -o " + quote(dir.path("a.exr"));
  const auto exr = runCommand("LD_DEBUG=libs " + kRender + " " + kCube + flags);
  ASSERT_EQ(exr.status, 0) << exr.err;
  EXPECT_NE(exr.err.find("libvdbappear_image"), std::string::npos) << "no loader log";
  EXPECT_EQ(exr.err.find("libOpenImageIO"), std::string::npos);
  const auto png = runCommand("LD_DEBUG=libs " + kRender + " " + kCube + flags + " --preview " + quote(dir.path("a.png")));
  ASSERT_EQ(png.status, 0) << png.err;
  EXPECT_NE(png.err.find("libvdbappear_oiio.so"), std::string::npos);
  EXPECT_NE(png.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_TRUE(exists(dir.path("a.png")));
}

TEST(RenderCli, SameImageWithOneThreadOrAll) {
  TempDir dir;
  const std::string a = dir.path("a.exr"), b = dir.path("b.exr");
  const std::string args = " --res 16 --spp 3 --seed 7 --view +y --sun 0,1,-1,3";
  ASSERT_EQ(runCommand(kRender + " " + kCube + args + " -j 1 -o " + quote(a)).status, 0);
  ASSERT_EQ(runCommand(kRender + " " + kCube + args + " -o " + quote(b)).status, 0);
  EXPECT_EQ(readImageChannels(a).values, readImageChannels(b).values);
}

// The medium is held in its compact form (docs/rendering.md), read in pieces: the same image, bit for
// bit, as the whole read made compact (--in-core) and as stdin; --full-precision renders the float
// grids; a medium whose grids the compact form does not hold is rendered from them, and -v says why.
TEST(RenderCli, TheMediumIsHeldCompactAndReadInPieces) {
  TempDir dir;
  const std::string twill = dir.path("twill.vdb");
  ASSERT_EQ(runCommand(quote(VDB_MAKE_MEDIUM) + " twill --yarns 2 --res 64 -o " + quote(twill)).status, 0);
  const std::string args = " --res 24 --spp 2 --seed 3 --view +z --sun 0.3,0.2,-1,3 -v --report ";
  const auto render = [&](const std::string& input, const std::string& flags, const std::string& name) {
    const auto r = runCommand(input + flags + args + quote(dir.path(name + ".json")) + " -o " + quote(dir.path(name + ".exr")));
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream report(dir.path(name + ".json"));
    return std::make_pair(r.err, nlohmann::json::parse(report)["medium_form"].get<std::string>());
  };
  const auto [pieces_err, pieces_form] = render(kRender + " " + quote(twill), " --memory 0.004", "pieces");
  const std::size_t said = pieces_err.find("the medium in compact form: ");
  ASSERT_NE(said, std::string::npos) << pieces_err;
  EXPECT_GE(std::stoi(pieces_err.substr(said + 28)), 4) << pieces_err;
  EXPECT_EQ(pieces_form, "compact");
  const auto [whole_err, whole_form] = render(kRender + " " + quote(twill), " --in-core", "whole");
  EXPECT_NE(whole_err.find("the medium in compact form: 1 piece read"), std::string::npos) << whole_err;
  render("cat " + quote(twill) + " | " + kRender + " -", "", "stdin");
  const auto [full_err, full_form] = render(kRender + " " + quote(twill), " --full-precision", "full");
  EXPECT_NE(full_err.find("rendered from its float grids: --full-precision"), std::string::npos) << full_err;
  EXPECT_EQ(full_form, "full precision");
  const std::vector<float> pieces = readImageChannels(dir.path("pieces.exr")).values;
  EXPECT_EQ(pieces, readImageChannels(dir.path("whole.exr")).values);
  EXPECT_EQ(pieces, readImageChannels(dir.path("stdin.exr")).values);
  EXPECT_NE(pieces, readImageChannels(dir.path("full.exr")).values) << "half-float albedo and S";

  MediumPtr emitting = readMedium(std::string(GOLDEN_DIR) + "/cube8.vdb");
  auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*emitting, "emission", openvdb::Vec3s(0.0f));
  emission->tree().setValueOn(openvdb::Coord(2, 2, 2), openvdb::Vec3s(1.0f));
  emitting->other_grids.push_back(emission);
  writeMedium(*emitting, dir.path("emitting.vdb"), "test");
  const auto [emitting_err, emitting_form] = render(kRender + " " + quote(dir.path("emitting.vdb")), "", "emitting");
  EXPECT_NE(emitting_err.find("grids the compact form does not hold: 'emission'"), std::string::npos) << emitting_err;
  EXPECT_EQ(emitting_form, "full precision");
}

TEST(RenderCli, ClusterAovMarksWhereEachClusterIsVisible) {
  TempDir dir;
  const std::string medium = dir.path("clusters.vdb"), out = dir.path("c.exr");
  MediumPtr cube = readMedium(std::string(GOLDEN_DIR) + "/cube8.vdb");
  auto cluster = test::namedGridLike<openvdb::Int32Grid>(*cube, "cluster", 0);
  for (auto it = cube->density->cbeginValueOn(); it; ++it) cluster->tree().setValue(it.getCoord(), it.getCoord().x() < 4 ? 0 : 1);
  cube->other_grids.push_back(cluster);
  writeMedium(*cube, medium, "test");
  ASSERT_EQ(runCommand(kRender + " " + quote(medium) + " -o " + quote(out) + " --res 16 --spp 16 --view +z --aov cluster").status, 0);
  const ImageChannels image = readImageChannels(out);
  ASSERT_EQ(image.names.size(), 5u);
  EXPECT_EQ(image.names[3], "cluster.0");
  const auto at = [&](int x, int y, int c) { return image.values[(std::size_t(y) * image.width + x) * 5 + c]; };
  // Seen from +z with +y up, world x grows to the right: cluster 0 (x < 4) on the left.
  const float left0 = at(5, 8, 3), left1 = at(5, 8, 4), right0 = at(10, 8, 3), right1 = at(10, 8, 4);
  EXPECT_TRUE(left0 > 0.5f && right1 > 0.5f && left1 < 0.5f && right0 < 0.5f)
      << left0 << " " << left1 << " " << right0 << " " << right1;
}

// --aov dweights: per cluster k and lobe slot j the layer dw.kK.jJ, and ds.kK their sum per channel.
TEST(RenderCli, GradientAovHasALayerPerClusterAndLobe) {
  TempDir dir;
  const std::string twill = dir.path("twill.vdb"), lobes = dir.path("lobes.vdb"), out = dir.path("g.exr");
  ASSERT_EQ(runCommand(quote(VDB_MAKE_MEDIUM) + " twill --yarns 2 --res 32 -o " + quote(twill)).status, 0);
  ASSERT_EQ(runCommand(quote(VDB_LOBE_CLUSTER) + " -f 4 --lobes 2 --clusters 2 " + quote(twill) + " " + quote(lobes)).status, 0);
  const auto r = runCommand(kRender + " " + quote(lobes) + " -o " + quote(out) + " --res 12 --spp 4 --aov dweights");
  ASSERT_EQ(r.status, 0) << r.err;
  const ImageChannels image = readImageChannels(out);
  ASSERT_EQ(image.names.size(), 3u + 2 * (2 * 3 + 3));
  const std::size_t n = image.names.size();
  double sum = 0;
  for (int k = 0; k < 2; ++k)
    for (const char* c : {"R", "G", "B"}) {
      const int ds = image.find(fmt::format("ds.k{}.{}", k, c)), dw0 = image.find(fmt::format("dw.k{}.j0.{}", k, c)),
                dw1 = image.find(fmt::format("dw.k{}.j1.{}", k, c));
      ASSERT_TRUE(ds >= 0 && dw0 >= 0 && dw1 >= 0) << k << c;
      for (std::size_t p = 0; p < std::size_t(image.width) * image.height; ++p) {
        const float* v = &image.values[p * n];
        EXPECT_NEAR(v[ds], v[dw0] + v[dw1], 1e-5);
        sum += v[dw0];
      }
    }
  EXPECT_GT(sum, 0);  // the weights make the fabric brighter
}

TEST(RenderCli, FlagsOverrideTheSceneFile) {
  TempDir dir;
  const std::string scene = dir.path("scene.json"), out = dir.path("s.exr"), report = dir.path("r.json");
  std::ofstream(scene) << R"({"medium": ")" << std::string(GOLDEN_DIR) + "/cube8.vdb"
                       << R"(", "resolution": [10, 6], "spp": 2, "camera": {"view": "-z", "fov": 40},
                             "lights": [{"type": "quad", "corner": [-1, -1, 2], "edge1": [2, 0, 0], "edge2": [0, 2, 0],
                                         "radiance": 4}], "ground": {"albedo": 0.3}})";
  ASSERT_EQ(runCommand(kRender + " --scene " + quote(scene) + " -o " + quote(out) + " --report " + quote(report)).status, 0);
  EXPECT_EQ(readImageChannels(out).width, 10);
  ASSERT_EQ(runCommand(kRender + " --scene " + quote(scene) + " -o " + quote(out) + " --res 4x4 --spp 3 --report " +
                       quote(report)).status, 0);
  EXPECT_EQ(readImageChannels(out).width, 4);
  std::ifstream in(report);
  EXPECT_EQ(nlohmann::json::parse(in)["spp"], 3);
}

struct BadInput {
  std::string name, args, message;
};

// A glossy ground and a height field from a scene file (docs/rendering.md, docs/displacement.md):
// the flat map at height 0.25 under a straight-down sun is a Lambertian plane of its albedo; its bad
// input (a negative roughness, an unknown BRDF key, NaN heights, a missing map) gets one line
// naming the file and the key, and no output.
TEST(RenderCli, GlossyGroundAndHeightFieldFromASceneFile) {
  TempDir dir;
  const std::string map = dir.path("map.exr"), nan_map = dir.path("nan.exr"), out = dir.path("out.exr");
  ImageChannels heights;
  heights.width = 5;
  heights.height = 3;
  heights.names = {"height"};
  heights.values.assign(15, 0.25f);
  writeExr(heights, map);
  heights.values[7] = std::nanf("");
  writeExr(heights, nan_map);
  const auto write_scene = [&](const std::string& name, const std::string& extra) {
    const std::string path = dir.path(name);
    std::ofstream(path) << R"({"resolution": [6, 6], "spp": 4, "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 10},
      "lights": [{"type": "sun", "direction": [0, 0, -1], "strength": 3}],
      "ground": {"height": -1, "brdf": {"distribution": "beckmann", "roughness": 0.2, "specular": 0.5}},
      "height_fields": [{"file": "map.exr", "size": 4, "origin": [-2, -1, 0], "albedo": 0.6}])"
                        << extra << "}";
    return path;
  };
  ASSERT_EQ(runCommand(kRender + " --scene " + quote(write_scene("ok.json", "")) + " -o " + quote(out)).status, 0);
  const ImageChannels image = readImageChannels(out);
  const std::size_t stride = image.names.size(), red = std::size_t(image.find("R"));
  for (std::size_t p = 0; p < std::size_t(image.width * image.height); ++p)
    EXPECT_NEAR(image.values[p * stride + red], 0.6 * 3 / 3.14159265358979, 1e-3) << p;
  std::filesystem::remove(out);

  std::ofstream(dir.path("rough.json")) << R"({"ground": {"brdf": {"roughness": -1}}})";
  std::ofstream(dir.path("key.json")) << R"({"ground": {"brdf": {"rougness": 0.1}}})";
  std::ofstream(dir.path("nan.json")) << R"({"height_fields": [{"file": "nan.exr"}]})";
  std::ofstream(dir.path("missing.json")) << R"({"height_fields": [{"file": "none.exr"}]})";
  const std::vector<BadInput> cases{
      {"negative roughness", "--scene " + quote(dir.path("rough.json")), "rough.json: ground.brdf: microfacet roughness must be positive"},
      {"unknown BRDF key", "--scene " + quote(dir.path("key.json")), "key.json: ground.brdf.rougness: unknown key"},
      {"NaN height", "--scene " + quote(dir.path("nan.json")), "nan.exr: height at pixel (column 2, row 1 from the top) is not a finite number"},
      {"missing height map", "--scene " + quote(dir.path("missing.json")), "none.exr"},
  };
  for (const BadInput& c : cases) {
    const auto r = runCommand(kRender + " " + kCube + " " + c.args + " -o " + quote(out));
    EXPECT_NE(r.status, 0) << c.name;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.name << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << c.name << ": " << r.err;
    EXPECT_FALSE(exists(out)) << c.name;
  }
}

TEST(RenderCli, BadInputFailsWithOneLineAndNoOutput) {
  TempDir dir;
  const std::string out = dir.path("out.exr");
  const std::string truncated = dir.path("truncated.vdb"), scene = dir.path("bad.json"), typo = dir.path("typo.json"),
                    sunless = dir.path("sunless.json"), interp = dir.path("interp.json"), strategy = dir.path("strategy.json"),
                    seed = dir.path("seed.json"), wide = dir.path("wide.json"), spp = dir.path("spp.json");
  {
    std::ifstream in(std::string(GOLDEN_DIR) + "/cube8.vdb", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::ofstream(scene) << R"({"lights": [{"type": "laser"}]})";
    std::ofstream(typo) << R"({"sppp": 4})";
    std::ofstream(sunless) << R"({"lights": [{"type": "sun", "strength": 3}]})";
    std::ofstream(interp) << R"({"interp": "anreest"})";  // found by the scene fuzz harness: named neither file nor key
    std::ofstream(strategy) << R"({"strategy": "guess"})";
    std::ofstream(seed) << R"({"seed": 1e50})";  // found by the scene fuzz harness: UB converting to an integer
    std::ofstream(wide) << R"({"resolution": [4294967312, 16]})";  // 2^32 + 16: was read as 16
    std::ofstream(spp) << R"({"spp": 2.5})";  // was read as 2
  }
  const std::vector<BadInput> cases{
      {"missing medium", quote(dir.path("none.vdb")), "none.vdb: no such file"},
      {"truncated medium", quote(truncated), "truncated.vdb"},
      {"no medium", "", "nothing to render"},
      {"bad resolution", kCube + " --res 0x4", "--res"},
      {"bad view", kCube + " --view +w", "--view '+w'"},
      {"bad interp", kCube + " --interp cubic", "interpolation 'cubic'"},
      {"bad strategy", kCube + " --strategy guess", "light strategy 'guess'"},
      {"two-value colour", kCube + " --env 1,2", "--env: give one value or three"},
      {"unknown light type", kCube + " --scene " + quote(scene), "unknown light type 'laser'"},
      {"unknown scene key", kCube + " --scene " + quote(typo), "sppp: unknown key"},
      {"sun without direction", kCube + " --scene " + quote(sunless), "lights[0]"},
      {"bad interp in a scene", kCube + " --scene " + quote(interp), "interp.json: interp: interpolation 'anreest'"},
      {"bad strategy in a scene", kCube + " --scene " + quote(strategy), "strategy.json: strategy: light strategy 'guess'"},
      {"seed out of range in a scene", kCube + " --scene " + quote(seed), "seed.json: seed: expected an integer in 0..18446744073709551615, got 1e+50"},
      {"width beyond int in a scene", kCube + " --scene " + quote(wide), "wide.json: resolution: expected an integer in"},
      {"fractional spp in a scene", kCube + " --scene " + quote(spp), "spp.json: spp: expected an integer in"},
      {"cluster AOV without clusters", kCube + " --aov cluster", "--aov cluster needs a medium with a 'cluster' grid"},
      {"gradient AOV without lobes", kCube + " --aov dweights", "--aov dweights needs a multi-lobe medium"},
      {"unknown AOV", kCube + " --aov normals", "--aov 'normals'"},
      {"missing scene", kCube + " --scene " + quote(dir.path("none.json")), "cannot open the scene file"},
      {"target without position", kCube + " --camera-target 0,0,0", "--camera-target needs --camera-pos"},
      {"camera at its target", kCube + " --camera-pos 1,1,1 --camera-target 1,1,1", "position and target coincide"},
      {"missing mesh", kCube + " --mesh " + quote(dir.path("none.obj")), "none.obj: no such mesh file"},
      {"missing env map", kCube + " --env-map " + quote(dir.path("none.exr")), "none.exr: no such image file"},
      {"zero spp", kCube + " --spp 0", "--spp must be >= 1"},
      {"negative seed", kCube + " --seed -1", "--seed"},
      {"unwritable report", kCube + " --report " + quote(dir.path("missing/r.json")), "no such folder"},
      {"unknown flag", kCube + " --bogus", "bogus"},
  };
  for (const BadInput& c : cases) {
    const auto r = runCommand(kRender + " " + c.args + " -o " + quote(out));
    EXPECT_NE(r.status, 0) << c.name;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(exists(out)) << c.name;
  }
  const auto aov = runCommand(kRender + " " + kCube + " --aov variance -o " + quote(dir.path("x.png")));
  EXPECT_NE(aov.status, 0);
  EXPECT_NE(aov.err.find("x.png: AOVs need an .exr output"), std::string::npos) << aov.err;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path("")) || !exists(dir.path("x.png")));
}

}  // namespace
}  // namespace vdbappear
