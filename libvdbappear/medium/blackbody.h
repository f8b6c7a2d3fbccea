#pragma once
// Black-body emission as Blender Cycles' Principled Volume makes it from a temperature attribute
// (docs/medium.md §3b), so that a fire read with `--grid emission=blackbody:temperature` (or
// `--from blender`) glows as it does in Cycles. Light header.

#include "libvdbappear/math/rgb.h"

#include <vector>

namespace vdbappear {

// The colour of a black body at `kelvin` in linear Rec.709 (D65), normalised to luminance 1:
// Planck's law through the CIE 1931 2-degree observer, 360-830 nm at 1 nm, the observer as the
// multi-lobe Gaussian fit of Wyman, Sloan and Shirley (JCGT 2013). Temperatures outside
// [800, 12000] K read as the nearer end, as Cycles' blackbody does. Channels outside Rec.709's gamut
// are negative (red at low temperatures needs negative blue).
Rgb blackbodyColour(double kelvin);

// blackbodyColour every 5 K over [800, 12000], read linearly: for converting whole grids.
class BlackbodyTable {
 public:
  BlackbodyTable();
  Rgb operator()(double kelvin) const;

 private:
  std::vector<Rgb> colours_;
};

// Principled Volume's blackbody inputs (Cycles' defaults, and Quick Smoke's fire: intensity 1).
struct PrincipledBlackbody {
  double kelvin = 1000;   // "Temperature": kelvin per unit of the temperature attribute
  double intensity = 1;   // "Blackbody Intensity", in [0, 1]
  Rgb tint = Rgb::Ones(); // "Blackbody Tint"
};

// The light emitted per unit length for attribute value `attribute` (Cycles' svm principled volume):
// T = kelvin * max(attribute, 0), and tint * sigma / pi * 1e-6 * mix(1, T^4, intensity) * colour(T)
// (Stefan-Boltzmann, sigma = 5.670373e-8); nothing where the intensity or that product is at most
// Cycles' cutoff 1e-5 (below about 150 K at intensity 1), so that cold voxels emit nothing and do not
// raise the majorant; each channel clamped at 0: the contract's emission is
// non-negative, where Cycles would subtract the light outside Rec.709's gamut (under 8% of a channel,
// in blue below 2000 K).
Rgb principledBlackbodyEmission(double attribute, const PrincipledBlackbody& settings, const BlackbodyTable& table);

}  // namespace vdbappear
