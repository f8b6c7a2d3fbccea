#include "libvdbappear/image/height_map_file.h"

#include "libvdbappear/surface/height_field_mesh.h"

#include <algorithm>

namespace vdbappear {

ImageChannels heightMapImage(const HeightField& field, double height_scale) {
  ImageChannels image;
  image.width = field.verticesX();
  image.height = field.verticesY();
  image.names = {"Y"};
  image.values.resize(std::size_t(image.width) * image.height);
  for (int j = 0; j < field.verticesY(); ++j)
    for (int i = 0; i < field.verticesX(); ++i)
      image.values[std::size_t(field.verticesY() - 1 - j) * image.width + i] = float(field.at(i, j) / height_scale);
  return image;
}

void writeHeightMap(const HeightField& field, const std::string& path, double height_scale) {
  writeExr(heightMapImage(field, height_scale), path);
}

HeightField readHeightMap(const std::string& path, double size, double height_scale) {
  const RgbImage image = readRgbImage(path);
  HeightField field = heightFieldFromImage(image, size / std::max(1, image.width - 1), path);
  for (int j = 0; j < field.verticesY(); ++j)
    for (int i = 0; i < field.verticesX(); ++i) field.at(i, j) *= height_scale;
  return field;
}

}  // namespace vdbappear
