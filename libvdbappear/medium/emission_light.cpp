#include "libvdbappear/medium/emission_light.h"

#include "libvdbappear/io/set_active_values.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

namespace vdbappear {

PrincipledBlackbody blackbodySettings(const openvdb::FloatGrid& temperature) {
  PrincipledBlackbody settings;
  settings.kelvin = 1;
  settings.intensity = blackbodyIntensityMetadata(temperature).value_or(1.0);
  return settings;
}

namespace {

template <typename GridT>
typename GridT::Ptr typedOtherGrid(const Medium& medium, const char* name, const char* expected) {
  for (const auto& grid : medium.other_grids)
    if (grid->getName() == name && !grid->isType<GridT>())
      throw MediumError(fmt::format("{}: grid '{}': holds {} values, expected {}", medium.source, name,
                                    grid->valueType(), expected));
  return findOtherGrid<GridT>(medium, name);
}

}  // namespace

openvdb::FloatGrid::Ptr blackbodyTemperatureGrid(const Medium& medium) {
  return typedOtherGrid<openvdb::FloatGrid>(medium, grid_names::kBlackbodyTemperature, "float");
}

openvdb::Vec3SGrid::Ptr emissionGrid(const Medium& medium) {
  return typedOtherGrid<openvdb::Vec3SGrid>(medium, grid_names::kEmission, "vec3s");
}

openvdb::Vec3SGrid::Ptr blackbodyLight(const openvdb::FloatGrid& temperature, const PrincipledBlackbody& settings) {
  auto light = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  light->setName(grid_names::kEmission);
  light->setTransform(temperature.transform().copy());
  light->tree().topologyUnion(temperature.tree());
  const BlackbodyTable table;
  auto lightOf = [&](float kelvin) {
    const Rgb e = principledBlackbodyEmission(kelvin, settings, table);
    return openvdb::Vec3s(float(e[0]), float(e[1]), float(e[2]));
  };
  setActiveValues(*light, [&](const openvdb::Coord& ijk, const openvdb::Vec3s&) {
    return lightOf(temperature.tree().getValue(ijk));
  });
  return light;
}

openvdb::Vec3SGrid::Ptr voxelEmission(const Medium& medium) {
  const auto emission = emissionGrid(medium);
  const auto temperature = blackbodyTemperatureGrid(medium);
  if (!temperature) return emission;
  auto light = blackbodyLight(*temperature, blackbodySettings(*temperature));
  if (!emission) return light;
  auto sum = emission->deepCopy();
  sum->tree().topologyUnion(light->tree());
  sum->tree().voxelizeActiveTiles();  // the light varies within a tile of the emission
  setActiveValues(*sum, [&](const openvdb::Coord& ijk, const openvdb::Vec3s& e) { return e + light->tree().getValue(ijk); });
  return sum;
}

}  // namespace vdbappear
