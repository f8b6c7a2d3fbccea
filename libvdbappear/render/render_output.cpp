#include "libvdbappear/render/render_output.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>


namespace vdbappear {


ImageChannels renderChannels(const RenderResult& result, const RenderOutputs& aovs) {
  ImageChannels image;
  image.width = result.width;
  image.height = result.height;
  image.names = {"R", "G", "B"};
  if (aovs.alpha) image.names.push_back("A");
  if (aovs.variance) image.names.insert(image.names.end(), {"variance.R", "variance.G", "variance.B"});
  const int K = aovs.clusters ? result.cluster_count : 0;
  for (int k = 0; k < K; ++k) image.names.push_back(fmt::format("cluster.{}", k));
  const int G = aovs.weight_gradients ? result.gradient_clusters : 0, m = result.gradient_lobes;
  for (int k = 0; k < G; ++k) {
    for (int j = 0; j < m; ++j)
      for (const char* c : {"R", "G", "B"}) image.names.push_back(fmt::format("dw.k{}.j{}.{}", k, j, c));
    for (const char* c : {"R", "G", "B"}) image.names.push_back(fmt::format("ds.k{}.{}", k, c));
  }
  for (const auto& [name, values] : result.extra_channels) image.names.push_back(name);
  const std::size_t n = image.names.size(), pixels = std::size_t(result.width) * result.height;
  image.values.resize(pixels * n);
  for (std::size_t i = 0; i < pixels; ++i) {
    float* out = &image.values[i * n];
    for (int c = 0; c < 3; ++c) *out++ = result.mean[3 * i + c];
    if (aovs.alpha) *out++ = result.alpha[i];
    if (aovs.variance)
      for (int c = 0; c < 3; ++c) *out++ = result.variance[3 * i + c];
    for (int k = 0; k < K; ++k) *out++ = result.cluster_coverage[i * K + k];
    for (int k = 0; k < G; ++k) {
      const float* dw = &result.weight_gradients[(i * G + k) * m * 3];
      for (int c = 0; c < 3 * m; ++c) *out++ = dw[c];
      for (int c = 0; c < 3; ++c) {
        double ds = 0;
        for (int j = 0; j < m; ++j) ds += dw[3 * j + c];
        *out++ = float(ds);
      }
    }
    for (const auto& extra : result.extra_channels) *out++ = extra.second[i];
  }
  return image;
}

RgbImage renderRgb(const RenderResult& result) {
  RgbImage image(result.width, result.height);
  image.pixels = result.mean;
  return image;
}

void checkRenderOutputs(const RenderOutputs& outputs) {
  const bool aovs = outputs.alpha || outputs.variance || outputs.clusters || outputs.weight_gradients || outputs.subsurface ||
                    outputs.pixel_seconds;
  if (aovs && imageFormat(outputs.image) != "exr")
    throw MediumError(fmt::format("{}: AOVs need an .exr output", outputs.image));
  if (!outputs.preview.empty()) imageFormat(outputs.preview);
}

void writeRenderOutputs(const RenderResult& result, const RenderOutputs& outputs) {
  checkRenderOutputs(outputs);
  if (imageFormat(outputs.image) == "exr") {
    writeExr(renderChannels(result, outputs), outputs.image);
  } else {
    writeImage(renderRgb(result), outputs.image);
  }
  if (!outputs.preview.empty()) writeImage(renderRgb(result), outputs.preview);
}

}  // namespace vdbappear
