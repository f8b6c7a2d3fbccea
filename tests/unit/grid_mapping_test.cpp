// io/grid_mapping.h: foreign grids read as the medium contract's (docs/medium.md §12): the rule
// syntax, each way of making a grid checked voxel by voxel against the file's grids, and one clear
// error for each kind of bad mapping.
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace vdbappear {
namespace {

using openvdb::Coord;
using openvdb::Vec3s;
using test::TempDir;

GridMapping mappingOf(std::initializer_list<const char*> rules) {
  GridMapping mapping;
  for (const char* rule : rules) addGridRule(mapping, parseGridRule(rule));
  return mapping;
}

std::string ruleError(const std::string& text) {
  try {
    parseGridRule(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

// A foreign file: density 2 on a 4^3 block, a Houdini-style `Cd` (vec3s), three float colour
// channels, and an int grid; the colour varies per voxel so a misplaced value shows.
struct ForeignFile {
  TempDir dir;
  std::string path = dir.path("foreign.vdb");
  ForeignFile(float colour_scale = 1) {
    auto transform = openvdb::math::Transform::createLinearTransform(0.25);
    auto density = openvdb::FloatGrid::create(0.0f);
    auto cd = openvdb::Vec3SGrid::create(Vec3s(0.0f));
    std::array<openvdb::FloatGrid::Ptr, 3> channel = {openvdb::FloatGrid::create(0.0f), openvdb::FloatGrid::create(0.0f),
                                                      openvdb::FloatGrid::create(0.0f)};
    auto ids = openvdb::Int32Grid::create(0);
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 4; ++y)
        for (int z = 0; z < 4; ++z) {
          const Coord ijk(x, y, z);
          density->tree().setValue(ijk, 2.0f);
          cd->tree().setValue(ijk, colourAt(ijk) * colour_scale);
          for (int c = 0; c < 3; ++c) channel[c]->tree().setValue(ijk, colourAt(ijk)[c]);
          ids->tree().setValue(ijk, 1);
        }
    const char* names[] = {"density", "Cd", "color_r", "color_g", "color_b", "ids"};
    openvdb::GridPtrVec grids = {density, cd, channel[0], channel[1], channel[2], ids};
    for (std::size_t i = 0; i < grids.size(); ++i) {
      grids[i]->setName(names[i]);
      grids[i]->setTransform(transform);
    }
    test::writeRawVdb(path, grids);
  }
  static Vec3s colourAt(const Coord& ijk) { return Vec3s(0.1f + 0.2f * ijk.x(), 0.05f * ijk.y(), 0.9f - 0.1f * ijk.z()); }
  std::string error(const GridMapping& mapping) const {
    try {
      readMedium(path, mapping);
    } catch (const MediumError& e) {
      return e.what();
    }
    return "read";
  }
};

// Wherever there is density, the medium's albedo is the file's colour, voxel for voxel.
void expectAlbedoIsTheColour(const Medium& medium) {
  ASSERT_TRUE(medium.albedo);
  for (auto v = medium.density->cbeginValueOn(); v; ++v)
    EXPECT_EQ(medium.albedo->tree().getValue(v.getCoord()), ForeignFile::colourAt(v.getCoord())) << v.getCoord();
}

TEST(GridMapping, RulesParseAndPrintBack) {
  const GridRule rgb = parseGridRule("albedo=color_r,color_g,color_b");
  EXPECT_EQ(rgb.role, "albedo");
  EXPECT_EQ(rgb.sources, (std::vector<std::string>{"color_r", "color_g", "color_b"}));
  EXPECT_EQ(rgb.scale, 1);
  const GridRule scaled = parseGridRule("density=density:0.5");
  EXPECT_EQ(scaled.sources, (std::vector<std::string>{"density"}));
  EXPECT_EQ(scaled.scale, 0.5);
  const GridRule divided = parseGridRule("albedo=color_r,color_g,color_b/density");
  EXPECT_EQ(divided.sources.size(), 3u);
  EXPECT_EQ(divided.divisor, "density");
  for (const char* text : {"albedo=Cd", "albedo=color_r,color_g,color_b", "density=density:0.5", "hg_g=g:2",
                           "albedo=color_r,color_g,color_b/density", "albedo=Cd/density:2"})
    EXPECT_EQ(gridRuleText(parseGridRule(text)), text);
}

TEST(GridMapping, MalformedRulesSayWhy) {
  EXPECT_NE(ruleError("albedo").find("expected ROLE=GRID"), std::string::npos);
  EXPECT_NE(ruleError("colour=Cd").find("'colour' is not a grid of the medium contract"), std::string::npos);
  EXPECT_NE(ruleError("density=a,b,c").find("only albedo and emission are made from three grids"), std::string::npos);
  EXPECT_NE(ruleError("albedo=a,b").find("expected one grid, or three"), std::string::npos);
  EXPECT_NE(ruleError("albedo=").find("a grid name is empty"), std::string::npos);
  EXPECT_NE(ruleError("density=density/rho").find("only albedo is divided by a grid"), std::string::npos);
  for (const char* divisor : {"albedo=Cd/", "albedo=Cd/a,b", "albedo=Cd/a/b"})
    EXPECT_NE(ruleError(divisor).find("expected one grid name after '/'"), std::string::npos) << divisor;
  for (const char* scale : {"density=density:0", "density=density:-1", "density=density:x", "density=density:nan"})
    EXPECT_NE(ruleError(scale).find("is not a number > 0"), std::string::npos) << scale;
  GridMapping mapping = mappingOf({"albedo=Cd"});
  EXPECT_THROW(addGridRule(mapping, parseGridRule("albedo=color_r,color_g,color_b")), std::invalid_argument);
}

// albedo=Cd: the albedo is Cd voxel for voxel, and Cd is consumed (not kept as a foreign grid).
TEST(GridMapping, OneVectorGridBecomesTheAlbedo) {
  const ForeignFile file;
  const MediumPtr medium = readMedium(file.path, mappingOf({"albedo=Cd"}));
  expectAlbedoIsTheColour(*medium);
  for (const auto& grid : medium->other_grids) EXPECT_NE(grid->getName(), "Cd");
  // Negative control: without the mapping (and no preset), the medium is white.
  GridMapping none;
  none.preset = GridPreset::kNone;
  EXPECT_FALSE(readMedium(file.path, none)->albedo);
}

// albedo=color_r,color_g,color_b: the three channels in order.
TEST(GridMapping, ThreeFloatGridsBecomeTheAlbedosChannels) {
  const ForeignFile file;
  const MediumPtr medium = readMedium(file.path, mappingOf({"albedo=color_r,color_g,color_b"}));
  expectAlbedoIsTheColour(*medium);
  EXPECT_EQ(medium->albedo->activeVoxelCount(), medium->density->activeVoxelCount());
  for (const auto& grid : medium->other_grids) EXPECT_EQ(grid->getName().rfind("color_", 0), std::string::npos);
  // Channels in another order land in other channels (the order is the rule's).
  const MediumPtr swapped = readMedium(file.path, mappingOf({"albedo=color_b,color_g,color_r"}));
  const Coord ijk(3, 1, 2);
  EXPECT_EQ(swapped->albedo->tree().getValue(ijk)[0], ForeignFile::colourAt(ijk)[2]);
}

// density=density:0.5 and a grey albedo from one float grid.
TEST(GridMapping, ScalesAndGreyAlbedo) {
  const ForeignFile file;
  const MediumPtr medium = readMedium(file.path, mappingOf({"density=density:0.5", "albedo=color_g"}));
  EXPECT_EQ(medium->density->tree().getValue(Coord(1, 2, 3)), 1.0f);
  const Coord ijk(0, 3, 0);
  EXPECT_EQ(medium->albedo->tree().getValue(ijk), Vec3s(ForeignFile::colourAt(ijk)[1]));
}

// emission=Cd:2 and emission=color_g (a flame-like float grid, grey): the contract's RGB emission
// (docs/medium.md §3b), voxel for voxel, with the scale; a negative value is refused naming the rule.
TEST(GridMapping, EmissionFromAColourOrAGreyGrid) {
  const ForeignFile file;
  const MediumPtr rgb = readMedium(file.path, mappingOf({"emission=Cd:2"}));
  const auto emission = findOtherGrid<openvdb::Vec3SGrid>(*rgb, grid_names::kEmission);
  ASSERT_TRUE(emission);
  for (auto v = rgb->density->cbeginValueOn(); v; ++v)
    EXPECT_EQ(emission->tree().getValue(v.getCoord()), ForeignFile::colourAt(v.getCoord()) * 2.0f) << v.getCoord();
  EXPECT_FALSE(findOtherGrid<openvdb::Vec3SGrid>(*rgb, "Cd"));
  const MediumPtr grey = readMedium(file.path, mappingOf({"emission=color_g"}));
  const auto grey_emission = findOtherGrid<openvdb::Vec3SGrid>(*grey, grid_names::kEmission);
  ASSERT_TRUE(grey_emission) << "a float emission is read as RGB";
  EXPECT_EQ(grey_emission->tree().getValue(Coord(0, 3, 0)), Vec3s(ForeignFile::colourAt(Coord(0, 3, 0))[1]));
  const MediumPtr three = readMedium(file.path, mappingOf({"emission=color_r,color_g,color_b"}));
  EXPECT_EQ(findOtherGrid<openvdb::Vec3SGrid>(*three, grid_names::kEmission)->tree().getValue(Coord(1, 2, 3)),
            ForeignFile::colourAt(Coord(1, 2, 3)));
  EXPECT_NE(ruleError("emission=flame/density").find("only albedo is divided by a grid"), std::string::npos);
}

// albedo=.../density: a colour premultiplied by the density (Mantaflow's color_r, _g, _b) divided
// by it voxel for voxel; the density itself stays the medium's density.
TEST(GridMapping, ColourTimesDensityDividedByTheDensity) {
  const ForeignFile file;  // density 2: the channels read as colour x density give colour / 2
  const MediumPtr medium = readMedium(file.path, mappingOf({"albedo=color_r,color_g,color_b/density"}));
  ASSERT_TRUE(medium->albedo);
  for (auto v = medium->density->cbeginValueOn(); v; ++v) {
    EXPECT_EQ(v.getValue(), 2.0f);
    EXPECT_EQ(medium->albedo->tree().getValue(v.getCoord()), ForeignFile::colourAt(v.getCoord()) * 0.5f) << v.getCoord();
  }
  // A Cd twice the colour, premultiplied: divided, the colour itself, where undivided it is refused below.
  const ForeignFile premultiplied(2.0f);
  expectAlbedoIsTheColour(*readMedium(premultiplied.path, mappingOf({"albedo=Cd/density"})));
  // Overshoot clamps to 1: Cd four times the colour over density 2 is twice the colour.
  const ForeignFile over(4.0f);
  const MediumPtr clamped = readMedium(over.path, mappingOf({"albedo=Cd/density"}));
  const Coord ijk(0, 0, 0);  // colour (0.1, 0, 0.9): 0.2, 0, 1.8 -> 1
  EXPECT_EQ(clamped->albedo->tree().getValue(ijk), Vec3s(0.2f, 0.0f, 1.0f));
}

// Where the divisor is 0 or inactive, there is no medium: the albedo is the contract's 1.
TEST(GridMapping, NoDensityDividesToWhite) {
  TempDir dir;
  const std::string path = dir.path("smoke.vdb");
  auto transform = openvdb::math::Transform::createLinearTransform(0.5);
  auto density = openvdb::FloatGrid::create(0.0f);
  auto colour = openvdb::FloatGrid::create(0.0f);
  density->tree().setValue(Coord(0, 0, 0), 0.5f);
  density->tree().setValue(Coord(1, 0, 0), 0.0f);  // active, empty
  colour->tree().setValue(Coord(0, 0, 0), 0.25f);
  colour->tree().setValue(Coord(1, 0, 0), 0.3f);
  colour->tree().setValue(Coord(2, 0, 0), 0.3f);   // no density voxel at all
  density->setName("density");
  colour->setName("colour");
  density->setTransform(transform);
  colour->setTransform(transform);
  test::writeRawVdb(path, {density, colour});
  const MediumPtr medium = readMedium(path, mappingOf({"albedo=colour/density"}));
  EXPECT_EQ(medium->albedo->tree().getValue(Coord(0, 0, 0)), Vec3s(0.5f));
  EXPECT_EQ(medium->albedo->tree().getValue(Coord(1, 0, 0)), Vec3s(1.0f));
  EXPECT_EQ(medium->albedo->tree().getValue(Coord(2, 0, 0)), Vec3s(1.0f));
  // Negative control: undivided, the grey colour is read as it is.
  EXPECT_EQ(readMedium(path, mappingOf({"albedo=colour"}))->albedo->tree().getValue(Coord(0, 0, 0)), Vec3s(0.25f));
}

TEST(GridMapping, BadMappingsFailNamingTheFileTheRuleAndTheGrid) {
  const ForeignFile file;
  const std::string missing = file.error(mappingOf({"albedo=colour"}));
  EXPECT_NE(missing.find(file.path + ": --grid albedo=colour: no grid named 'colour' (the file has Cd, color_b, color_g, color_r, density, ids)"),
            std::string::npos)
      << missing;
  const std::string type = file.error(mappingOf({"albedo=ids"}));
  EXPECT_NE(type.find("--grid albedo=ids: grid 'ids' holds int32 values, expected vec3s or float"), std::string::npos) << type;
  const std::string three = file.error(mappingOf({"albedo=color_r,Cd,color_b"}));
  EXPECT_NE(three.find("grid 'Cd' holds vec3s values, expected float"), std::string::npos) << three;
  const std::string density = file.error(mappingOf({"density=Cd"}));
  EXPECT_NE(density.find("expected float"), std::string::npos) << density;
  // Values the role does not allow: the albedo 2 Cd would give.
  const ForeignFile bright(2.0f);
  const std::string range = bright.error(mappingOf({"albedo=Cd"}));
  EXPECT_NE(range.find("grid 'albedo': albedo"), std::string::npos) << range;
  EXPECT_NE(range.find("outside [0,1]"), std::string::npos) << range;
  EXPECT_NE(range.find("(made by --grid albedo=Cd)"), std::string::npos) << range;
  // A divisor that is missing or not a float grid.
  const std::string no_divisor = file.error(mappingOf({"albedo=Cd/rho"}));
  EXPECT_NE(no_divisor.find("--grid albedo=Cd/rho: no grid named 'rho'"), std::string::npos) << no_divisor;
  const std::string vector_divisor = file.error(mappingOf({"albedo=color_g/Cd"}));
  EXPECT_NE(vector_divisor.find("grid 'Cd' holds vec3s values, expected float"), std::string::npos) << vector_divisor;
}

// Grids combined voxel by voxel must share one transform: channels on another voxel size, or a
// divisor on one, are refused naming both grids (a negative control reads the matching pair).
TEST(GridMapping, GridsOnDifferentTransformsAreRefused) {
  TempDir dir;
  const auto write = [&](const std::string& file, const std::vector<std::pair<std::string, double>>& voxel_sizes) {
    openvdb::GridPtrVec grids;
    for (const auto& [name, voxel] : voxel_sizes) {
      auto grid = openvdb::FloatGrid::create(0.0f);
      grid->tree().setValue(Coord(0, 0, 0), 0.5f);
      grid->setName(name);
      grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
      grids.push_back(grid);
    }
    test::writeRawVdb(dir.path(file), grids);
    return dir.path(file);
  };
  const auto error = [&](const std::string& path, std::initializer_list<const char*> rules) {
    try {
      readMedium(path, mappingOf(rules));
    } catch (const MediumError& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  const std::string mixed =
      write("mixed.vdb", {{"density", 0.25}, {"r", 0.25}, {"g", 0.25}, {"b", 0.5}, {"rho_coarse", 0.5}});
  const std::string channels = error(mixed, {"albedo=r,g,b"});
  EXPECT_NE(channels.find(mixed + ": --grid albedo=r,g,b: grids 'r' and 'b' have different transforms"),
            std::string::npos)
      << channels;
  const std::string divisor = error(mixed, {"albedo=r/rho_coarse"});
  EXPECT_NE(divisor.find("--grid albedo=r/rho_coarse: grids 'r' and 'rho_coarse' have different transforms"),
            std::string::npos)
      << divisor;
  // Negative control: the same rules on grids that share the density's transform.
  const std::string same = write("same.vdb", {{"density", 0.25}, {"r", 0.25}, {"g", 0.25}, {"b", 0.25}});
  EXPECT_EQ(error(same, {"albedo=r,g,b/density"}), "read");
}

GridMapping presetOf(GridPreset preset, std::initializer_list<const char*> rules = {}) {
  GridMapping mapping = mappingOf(rules);
  mapping.preset = preset;
  return mapping;
}

std::string allNotes(const Medium& medium) {
  std::string text;
  for (const std::string& note : medium.read_notes) text += note + "\n";
  return text;
}

TEST(GridMapping, PresetsParseByName) {
  for (GridPreset preset : {GridPreset::kAuto, GridPreset::kNone, GridPreset::kBlender, GridPreset::kHoudini})
    EXPECT_EQ(parseGridPreset(gridPresetName(preset)), preset);
  try {
    parseGridPreset("maya");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'maya': expected auto, blender, houdini or none"), std::string::npos) << e.what();
  }
}

// With no albedo grid and no albedo rule, the default (auto) reads a Mantaflow colour divided by
// the density, as --grid albedo=color_r,color_g,color_b/density does, and says so in one note; the
// rule it applied is the medium's (what the optimiser's reference cache keys on). Mantaflow's
// channels come before a Cd in a file with both.
TEST(GridMapping, AutoReadsMantaflowColourAndSaysSo) {
  const ForeignFile file;  // density 2, colour channels and Cd
  const MediumPtr medium = readMedium(file.path);
  ASSERT_TRUE(medium->albedo);
  for (auto v = medium->density->cbeginValueOn(); v; ++v)
    EXPECT_EQ(medium->albedo->tree().getValue(v.getCoord()), ForeignFile::colourAt(v.getCoord()) * 0.5f) << v.getCoord();
  ASSERT_EQ(medium->read_notes.size(), 1u) << allNotes(*medium);
  EXPECT_EQ(medium->read_notes[0], file.path + ": Blender's smoke cache (Mantaflow): read as --grid "
                                               "albedo=color_r,color_g,color_b/density (--from none reads the grids as they are)");
  ASSERT_EQ(medium->grid_rules.size(), 1u);
  EXPECT_EQ(gridRuleText(medium->grid_rules[0]), "albedo=color_r,color_g,color_b/density");
}

// --from houdini reads Cd; --from none reads nothing and says nothing; an explicit albedo rule
// leaves the preset nothing to do.
TEST(GridMapping, ExplicitPresetsAndRulesWin) {
  const ForeignFile file;
  const MediumPtr houdini = readMedium(file.path, presetOf(GridPreset::kHoudini));
  expectAlbedoIsTheColour(*houdini);
  ASSERT_EQ(houdini->read_notes.size(), 1u) << allNotes(*houdini);
  EXPECT_EQ(houdini->read_notes[0], file.path + ": Houdini's Cd: read as --grid albedo=Cd");
  const MediumPtr none = readMedium(file.path, presetOf(GridPreset::kNone));
  EXPECT_FALSE(none->albedo);
  EXPECT_TRUE(none->read_notes.empty()) << allNotes(*none);
  EXPECT_TRUE(none->grid_rules.empty());
  const MediumPtr explicit_rule = readMedium(file.path, mappingOf({"albedo=color_g"}));
  EXPECT_EQ(explicit_rule->albedo->tree().getValue(Coord(0, 3, 0)), Vec3s(ForeignFile::colourAt(Coord(0, 3, 0))[1]));
  EXPECT_TRUE(explicit_rule->read_notes.empty()) << allNotes(*explicit_rule);
  // A medium of the contract, with an albedo grid, is read as it is.
  TempDir dir;
  const std::string contract = dir.path("contract.vdb");
  const MediumPtr with_albedo = readMedium(file.path, mappingOf({"albedo=Cd"}));
  writeMedium(*with_albedo, contract, "test");
  const MediumPtr again = readMedium(contract);
  EXPECT_TRUE(again->read_notes.empty()) << allNotes(*again);
  EXPECT_TRUE(again->grid_rules.empty());
}

// A Volume object's `color` under --from blender; Blender's preset on a file with none of its
// colour grids says so, and reads the grids as they are.
TEST(GridMapping, BlenderVolumeObjectColourAndAPresetWithNothingToMap) {
  TempDir dir;
  const auto write = [&](const std::string& file, const char* colour_name) {
    auto density = openvdb::FloatGrid::create(0.0f);
    auto colour = openvdb::Vec3SGrid::create(Vec3s(0.0f));
    density->tree().setValue(Coord(1, 1, 1), 3.0f);
    colour->tree().setValue(Coord(1, 1, 1), Vec3s(0.25f, 0.5f, 0.75f));
    density->setName("density");
    colour->setName(colour_name);
    test::writeRawVdb(dir.path(file), {density, colour});
    return dir.path(file);
  };
  const MediumPtr volume = readMedium(write("volume.vdb", "color"), presetOf(GridPreset::kBlender));
  EXPECT_EQ(volume->albedo->tree().getValue(Coord(1, 1, 1)), Vec3s(0.25f, 0.5f, 0.75f));
  EXPECT_NE(allNotes(*volume).find("Blender's Volume object: read as --grid albedo=color"), std::string::npos);
  const std::string houdini = write("houdini.vdb", "Cd");
  const MediumPtr nothing = readMedium(houdini, presetOf(GridPreset::kBlender));
  EXPECT_FALSE(nothing->albedo);
  EXPECT_EQ(allNotes(*nothing), houdini + ": --from blender: none of its colour grids (color_r, color_g, color_b; "
                                          "color): the grids are read as they are\n");
}

// A detected colour that is no albedo (a Cd up to 1.8) is left out with a note naming why, and the
// file reads as it is; asked for by name (--from houdini), it is an error naming the preset's rule.
TEST(GridMapping, DetectedColourOutsideTheAlbedoRangeIsLeftWithANote) {
  TempDir dir;
  const std::string path = dir.path("bright.vdb");
  auto density = openvdb::FloatGrid::create(0.0f);
  auto cd = openvdb::Vec3SGrid::create(Vec3s(0.0f));
  density->tree().setValue(Coord(0, 0, 0), 1.0f);
  cd->tree().setValue(Coord(0, 0, 0), Vec3s(1.8f, 0.4f, 0.4f));
  density->setName("density");
  cd->setName("Cd");
  test::writeRawVdb(path, {density, cd});
  const MediumPtr medium = readMedium(path);
  EXPECT_FALSE(medium->albedo);
  EXPECT_TRUE(medium->grid_rules.empty());
  const std::string notes = allNotes(*medium);
  EXPECT_NE(notes.find(path + ": Houdini's Cd: not read as --grid albedo=Cd, the grids are read as they are: grid "
                              "'albedo': albedo (1.8"),
            std::string::npos)
      << notes;
  try {
    readMedium(path, presetOf(GridPreset::kHoudini));
    FAIL() << "read";
  } catch (const MediumError& e) {
    EXPECT_NE(std::string(e.what()).find("outside [0,1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(made by --from houdini: --grid albedo=Cd)"), std::string::npos) << e.what();
  }
}

// Fire grids that no rule reads are named in a note: under --from houdini (no fire preset), or in a
// Blender file without `temperature`, which Blender's preset reads as blackbody light (emission_test.cpp).
// --from none is silent, and so are a mapped emission and a medium of the contract (with an albedo
// grid) that carries such a grid.
TEST(GridMapping, EmissionGridsAreNamedInANote) {
  TempDir dir;
  const std::string path = dir.path("fire.vdb");
  openvdb::GridPtrVec grids;
  for (const char* name : {"density", "flame", "temperature"}) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(Coord(0, 0, 0), 0.5f);
    grid->setName(name);
    grids.push_back(grid);
  }
  test::writeRawVdb(path, grids);
  const std::string unread = ": 'flame', 'temperature' hold fire or heat, not read as light: --grid "
                             "emission=blackbody:temperature reads it as Cycles' blackbody light (docs/medium.md section 3b)\n";
  EXPECT_EQ(allNotes(*readMedium(path, presetOf(GridPreset::kHoudini))),
            path + ": --from houdini: none of its colour grids (Cd): the grids are read as they are\n" + path + unread);
  EXPECT_NE(allNotes(*readMedium(path)).find("read as --grid emission=blackbody:temperature"), std::string::npos);
  EXPECT_EQ(allNotes(*readMedium(path)).find("not read as light"), std::string::npos) << "the preset reads the fire";
  EXPECT_TRUE(readMedium(path, mappingOf({"emission=flame:4"}))->read_notes.empty()) << "mapped: no note";
  EXPECT_TRUE(readMedium(path, presetOf(GridPreset::kNone))->read_notes.empty());
  grids.erase(grids.begin() + 2);  // no temperature: nothing for Blender's preset
  const std::string flame_only = dir.path("flame.vdb");
  test::writeRawVdb(flame_only, grids);
  EXPECT_EQ(allNotes(*readMedium(flame_only)), flame_only + ": 'flame' holds fire or heat, not read as light: --grid "
                                                            "emission=flame:STRENGTH reads it as light per unit length "
                                                            "(docs/medium.md section 3b)\n");
  auto albedo = openvdb::Vec3SGrid::create(Vec3s(0.0f));
  albedo->tree().setValue(Coord(0, 0, 0), Vec3s(0.5f));
  albedo->setName("albedo");
  grids.push_back(albedo);
  const std::string contract = dir.path("contract_with_fire.vdb");
  test::writeRawVdb(contract, grids);
  EXPECT_TRUE(readMedium(contract)->read_notes.empty()) << allNotes(*readMedium(contract));
}

}  // namespace
}  // namespace vdbappear
