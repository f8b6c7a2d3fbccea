#include "libvdbappear/prefilter/prefiltered_surface_file.h"

#include "libvdbappear/image/exr_file.h"
#include "libvdbappear/image/height_map_file.h"
#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

namespace vdbappear {
namespace {

using json = nlohmann::json;
constexpr const char* kFormat = "vdbappear prefiltered displacement";
constexpr int kVersion = 1;
constexpr const char* kLobeChannels[5] = {"A", "kappa", "X", "Y", "Z"};  // alpha, kappa, mu

std::string scalingName(ScalingKind kind) { return kind == ScalingKind::Shadowing ? "shadowing" : "interreflection"; }

ImageChannels emptyImage(int width, int height, std::vector<std::string> names) {
  ImageChannels image;
  image.width = width;
  image.height = height;
  image.names = std::move(names);
  image.values.assign(std::size_t(width) * height * image.names.size(), 0.0f);
  return image;
}

float& pixel(ImageChannels& image, int column, int row, int channel) {
  return image.values[(std::size_t(row) * image.width + column) * image.names.size() + channel];
}
float pixel(const ImageChannels& image, int column, int row, int channel) {
  return image.values[(std::size_t(row) * image.width + column) * image.names.size() + channel];
}

// Cell (u, v) is pixel (u, rows - 1 - v): the map reads upright from +z (§1).
ImageChannels lobeImage(const std::vector<VmfMixture>& ndfs, int cells_x, int cells_y) {
  std::size_t lobes = 1;
  for (const VmfMixture& d : ndfs) lobes = std::max(lobes, d.lobes.size());
  std::vector<std::string> names;
  for (std::size_t k = 0; k < lobes; ++k)
    for (const char* c : kLobeChannels) names.push_back(fmt::format("lobe{}.{}", k, c));
  ImageChannels image = emptyImage(cells_x, cells_y, names);
  for (int v = 0; v < cells_y; ++v)
    for (int u = 0; u < cells_x; ++u) {
      const VmfMixture& d = ndfs[std::size_t(u) + std::size_t(cells_x) * v];
      for (std::size_t k = 0; k < d.lobes.size(); ++k) {
        const VmfLobe& l = d.lobes[k];
        const double values[5] = {l.amplitude, l.kappa, l.mu.x(), l.mu.y(), l.mu.z()};
        for (int c = 0; c < 5; ++c) pixel(image, u, cells_y - 1 - v, int(5 * k) + c) = float(values[c]);
      }
    }
  return image;
}

ImageChannels rgbTable(const std::vector<Rgb>& values, int width, int height) {
  ImageChannels image = emptyImage(width, height, {"R", "G", "B"});
  for (int row = 0; row < height; ++row)
    for (int column = 0; column < width; ++column)
      for (int c = 0; c < 3; ++c) pixel(image, column, row, c) = float(values[std::size_t(row) * width + column][c]);
  return image;
}

// T's bin (a, b) is pixel (a, M - 1 - b); S's bin (wi bin ia + N ib, wo node oa + V ob) is pixel
// (column oa + V ob, row ia + N ib), V = N, or N + 2 with the view's horizon nodes.
std::vector<Rgb> spatialRows(const SpatialScaling& T) {
  const int M = T.resolution;
  std::vector<Rgb> rows(T.values.size());
  for (int b = 0; b < M; ++b)
    for (int a = 0; a < M; ++a) rows[std::size_t(M - 1 - b) * M + a] = T.values[std::size_t(a) + std::size_t(M) * b];
  return rows;
}

ImageChannels spatialImage(const SpatialScaling& T) { return rgbTable(spatialRows(T), T.resolution, T.resolution); }
// S's values, or the relief term's B on S's nodes.
ImageChannels angularImage(const AngularScaling& S, const std::vector<Rgb>& table) {
  return rgbTable(table, S.viewNodes() * S.viewNodes(), S.resolution * S.resolution);
}

Rgb pixelRgb(const ImageChannels& image, int column, int row) {
  return {pixel(image, column, row, 0), pixel(image, column, row, 1), pixel(image, column, row, 2)};
}

SpatialScaling spatialTable(const ImageChannels& image, int M) {
  SpatialScaling T;
  T.resolution = M;
  for (int b = 0; b < M; ++b)
    for (int a = 0; a < M; ++a) T.values.push_back(pixelRgb(image, a, M - 1 - b));
  return T;
}

AngularScaling angularTable(const ImageChannels& image, int N, bool view_horizon) {
  AngularScaling S;
  S.resolution = N;
  S.view_horizon = view_horizon;
  const int V = S.viewNodes();
  for (int row = 0; row < N * N; ++row)
    for (int column = 0; column < V * V; ++column) S.values.push_back(pixelRgb(image, column, row));
  return S;
}

void fail(const std::string& path, const std::string& what) { throw MediumError(fmt::format("{}: {}", path, what)); }

ImageChannels readPart(const std::string& path, int width, int height, int min_channels) {
  if (!std::filesystem::exists(path)) fail(path, "missing (a part of a prefiltered displacement map)");
  ImageChannels image = readExrChannels(path);
  if (image.width != width || image.height != height || int(image.names.size()) < min_channels)
    fail(path, fmt::format("expected {} x {} pixels with at least {} channels, found {} x {} with {}", width, height,
                           min_channels, image.width, image.height, image.names.size()));
  for (float value : image.values)
    if (!std::isfinite(value)) fail(path, "holds a value that is not finite");
  return image;
}

}  // namespace

std::string prefilteredPartPath(const std::string& manifest_path, const std::string& part) {
  std::filesystem::path p(manifest_path);
  const std::string stem = p.extension() == ".json" ? p.stem().string() : p.filename().string();
  return (p.parent_path() / (stem + "." + part + ".exr")).string();
}

void writePrefilteredSurface(const PrefilteredSurfaceFile& file, const std::string& manifest_path, const json& extra) {
  const PrefilteredSurface& s = file.surface;
  const int cells_x = s.height.cellsX(), cells_y = s.height.cellsY();
  std::vector<std::pair<std::string, ImageChannels>> parts = {
      {"height", heightMapImage(s.height, file.info.height_scale)},
      {"lobes", lobeImage(s.ndfs, cells_x, cells_y)},
      {"T", spatialImage(s.scaling.T)},
      {"S", angularImage(s.scaling.S, s.scaling.S.values)}};
  const bool relief = !s.scaling.S.relief_slopes.empty();
  if (relief) parts.emplace_back("B", angularImage(s.scaling.S, s.scaling.S.relief_slopes));
  for (std::size_t k = 0; k < s.stretched.size(); ++k) {
    parts.emplace_back(fmt::format("stretch{}.T", k + 1), spatialImage(s.stretched[k].scaling.T));
    const AngularScaling& S = s.stretched[k].scaling.S;
    parts.emplace_back(fmt::format("stretch{}.S", k + 1), angularImage(S, S.values));
    if (relief) parts.emplace_back(fmt::format("stretch{}.B", k + 1), angularImage(S, S.relief_slopes));
  }
  std::vector<std::unique_ptr<AtomicFile>> outputs;
  json files;
  for (const auto& [part, image] : parts) {
    const std::string path = prefilteredPartPath(manifest_path, part);
    outputs.push_back(std::make_unique<AtomicFile>(path));
    writeExrChannels(image, ExrPixelType::float32, outputs.back()->temporaryPath(), path);
    files[part] = std::filesystem::path(path).filename().string();
  }
  json stretched = json::array();
  for (std::size_t k = 0; k < s.stretched.size(); ++k) {
    const Eigen::Matrix2d& m = s.stretched[k].stretch.matrix();
    const std::string name = fmt::format("stretch{}", k + 1);
    stretched.push_back({{"stretch", {{m(0, 0), m(0, 1)}, {m(1, 0), m(1, 1)}}},
                         {"T", files[name + ".T"]},
                         {"S", files[name + ".S"]}});
    if (relief) stretched.back()["B"] = files[name + ".B"];
    files.erase(name + ".T");
    files.erase(name + ".S");
    files.erase(name + ".B");
  }
  json manifest = {{"format", kFormat},
                   {"version", kVersion},
                   {"source", file.info.source},
                   {"factor", file.info.factor},
                   {"size", file.info.size},
                   {"height_scale", file.info.height_scale},
                   {"cells", {cells_x, cells_y}},
                   {"brdf", brdfToJson(file.base)},
                   {"scaling", scalingName(file.info.scaling)},
                   {"spatial_resolution", s.scaling.T.resolution},
                   {"angular_resolution", s.scaling.S.resolution},
                   {"view_horizon", s.scaling.S.view_horizon},
                   {"files", files},
                   {"stretched", stretched},
                   {"settings", extra}};
  if (relief) manifest["relief_radius"] = s.scaling.relief.radius;
  AtomicFile output(manifest_path);
  {
    std::ofstream stream(output.temporaryPath());
    stream << manifest.dump(2) << "\n";
    if (!stream) fail(manifest_path, "cannot be written");
  }
  for (auto& part : outputs) part->commit();
  output.commit();
}

PrefilteredSurfaceFile readPrefilteredSurface(const std::string& manifest_path) {
  std::ifstream stream(manifest_path);
  if (!stream) fail(manifest_path, "cannot be opened");
  json m;
  try {
    m = json::parse(stream);
    if (m.value("format", "") != kFormat) fail(manifest_path, "not a prefiltered displacement map (no \"format\": \"" + std::string(kFormat) + "\")");
    if (m.at("version").get<int>() != kVersion) fail(manifest_path, "unknown version");
    PrefilteredSurfaceInfo info;
    info.source = m.at("source").get<std::string>();
    info.factor = m.at("factor").get<int>();
    info.size = m.at("size").get<double>();
    info.height_scale = m.at("height_scale").get<double>();
    info.scaling = m.at("scaling").get<std::string>() == "shadowing" ? ScalingKind::Shadowing : ScalingKind::Interreflection;
    const int cells_x = m.at("cells").at(0).get<int>(), cells_y = m.at("cells").at(1).get<int>();
    const int M = m.at("spatial_resolution").get<int>(), N = m.at("angular_resolution").get<int>();
    if (cells_x < 1 || cells_y < 1 || M < 1 || N < 1 || !(info.size > 0) || !(info.height_scale > 0))
      fail(manifest_path, "cells, table resolutions, size and height_scale must be positive");
    const MicrofacetBrdf base = brdfFromJson(m.at("brdf"), manifest_path, "brdf");
    const std::filesystem::path folder = std::filesystem::path(manifest_path).parent_path();
    const auto part = [&](const char* name) { return (folder / m.at("files").at(name).get<std::string>()).string(); };

    PrefilteredSurface s;
    const ImageChannels height = readPart(part("height"), cells_x + 1, cells_y + 1, 1);
    s.height = HeightField(cells_x, cells_y, info.size / cells_x);
    for (int j = 0; j <= cells_y; ++j)
      for (int i = 0; i <= cells_x; ++i) s.height.at(i, j) = pixel(height, i, cells_y - j, 0) * info.height_scale;
    const ImageChannels lobes = readPart(part("lobes"), cells_x, cells_y, 5);
    s.ndfs.resize(std::size_t(cells_x) * cells_y);
    for (int k = 0; lobes.find(fmt::format("lobe{}.A", k)) >= 0; ++k) {
      int channel[5];
      for (int c = 0; c < 5; ++c) {
        const std::string name = fmt::format("lobe{}.{}", k, kLobeChannels[c]);
        if ((channel[c] = lobes.find(name)) < 0) fail(part("lobes"), "no channel " + name);
      }
      for (int v = 0; v < cells_y; ++v)
        for (int u = 0; u < cells_x; ++u) {
          const auto c = [&](int i) { return double(pixel(lobes, u, cells_y - 1 - v, channel[i])); };
          if (c(0) <= 0) continue;  // an unused lobe
          if (c(1) < 0) fail(part("lobes"), fmt::format("cell ({}, {}): negative kappa", u, v));
          s.ndfs[std::size_t(u) + std::size_t(cells_x) * v].lobes.push_back({c(0), c(1), Vec3(c(2), c(3), c(4)).normalized()});
        }
    }
    const bool view_horizon = m.value("view_horizon", false);  // wo's horizon nodes (S's width (N + 2)^2)
    const int V = view_horizon ? N + 2 : N;
    // The relief term (docs/displacement.md §6): B beside each S, and z from h_low.
    const int relief_radius = m.value("relief_radius", 0);
    if (relief_radius < 0 || relief_radius > widestReliefRadius(cells_x, cells_y))
      fail(manifest_path, "\"relief_radius\" must be 0 (none) or an r >= 1 whose 2 r + 1 cells fit in the coarse map");
    const CellRelief relief = relief_radius > 0 ? cellRelief(s.height, relief_radius) : CellRelief();
    const auto tables = [&](const json& files) {
      const auto path = [&](const char* name) { return (folder / files.at(name).get<std::string>()).string(); };
      FactorizedScaling scaling;
      scaling.T = spatialTable(readPart(path("T"), M, M, 3), M);
      scaling.S = angularTable(readPart(path("S"), V * V, N * N, 3), N, view_horizon);
      if (relief_radius > 0) {
        scaling.S.relief_slopes = angularTable(readPart(path("B"), V * V, N * N, 3), N, view_horizon).values;
        scaling.relief = relief;
      }
      return scaling;
    };
    s.scaling = tables(m.at("files"));
    for (const json& table : m.value("stretched", json::array())) {
      const json& rows = table.at("stretch");
      Eigen::Matrix2d stretch;
      stretch << rows.at(0).at(0).get<double>(), rows.at(0).at(1).get<double>(), rows.at(1).at(0).get<double>(),
          rows.at(1).at(1).get<double>();
      if (!stretch.allFinite() || !(stretch.determinant() > 0))
        fail(manifest_path, "a \"stretched\" table's \"stretch\" must be finite with a positive determinant");
      s.stretched.push_back({TileStretch(stretch), tables(table)});
    }
    return {std::move(s), base, info};
  } catch (const json::exception& e) {
    fail(manifest_path, e.what());
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const MediumError*>(&e)) throw;
    throw MediumError(e.what());
  }
  throw MediumError(manifest_path);  // not reached
}

}  // namespace vdbappear
