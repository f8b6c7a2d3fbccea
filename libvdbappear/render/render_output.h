#pragma once
// Writing a render: a linear float EXR with R, G, B and the requested AOVs, or an sRGB PNG, and an
// optional PNG preview. Part of libvdbappear_image.
//
// AOV channels: "A", the medium's alpha (the share of camera rays with a real collision in it: an
// estimate of 1 - transmittance), "variance.R/G/B", the variance of each pixel's mean (sample
// variance / spp), and
// "cluster.K" for K = 0 .. clusters-1, the share of the pixel's camera rays whose first real
// collision lies in a voxel of cluster K (> 0: cluster K is directly visible in the pixel, the
// pixel sets of the restricted means of §6.3, downsampling paper).
// Gradient images (render/path_gradients.h): "dw.kK.jJ.R/G/B", the derivative of the pixel with
// respect to a factor w on the weights of lobe slot J in cluster K, at w = 1 (Eq. 23), and
// "ds.kK.R/G/B", with respect to a colour scale s_K of that channel at s = 1 (Eq. 19): the sum over
// J of dw.kK.jJ, since I^c depends on s^c and w_kj only through their products.
// Then RenderResult::extra_channels by name: the subsurface AOVs "sss.hit", "sss.cache",
// "sss.S.R/G/B", "sss.S1.R/G/B", "sss.gradS.R/G/B", "sss.V.R/G/B" (render/subsurface_passes.h).

#include "libvdbappear/image/image_file.h"
#include "libvdbappear/render/render_image.h"

#include <string>

namespace vdbappear {

struct RenderOutputs {
  std::string image;    // .exr (float, with AOVs) or .png (sRGB)
  std::string preview;  // optional .png
  bool alpha = false;
  bool variance = false;
  bool clusters = false;
  bool weight_gradients = false;
  bool subsurface = false;  // RenderResult::extra_channels hold the subsurface AOVs (checked here only)
  bool pixel_seconds = false;  // RenderResult::extra_channels hold "time" (checked here only)
};

ImageChannels renderChannels(const RenderResult& result, const RenderOutputs& aovs);
RgbImage renderRgb(const RenderResult& result);
// Throws MediumError when the outputs cannot be written as asked (AOVs in a file that is not EXR,
// no extension): tools call it before rendering, writeRenderOutputs again before writing.
void checkRenderOutputs(const RenderOutputs& outputs);
void writeRenderOutputs(const RenderResult& result, const RenderOutputs& outputs);

}  // namespace vdbappear
