#pragma once
// What a medium's `emission` grid means (docs/medium.md §3b): the field's two conventions, which
// are not interchangeable. Light header.

#include <optional>
#include <string>

namespace vdbappear {

struct Medium;

enum class EmissionConvention {
  kCycles,  // E: radiance added per unit length, whatever the density (Blender Cycles)
  kPbrt,    // Le: emitted by the absorbing part, sigma_a Le per unit length (pbrt-v4, Mitsuba 3)
};

std::optional<EmissionConvention> parseEmissionConvention(const std::string& name);
const char* emissionConventionName(EmissionConvention convention);

// The convention of the medium's metadata `emission_convention` (kCycles when absent). Throws
// MediumError naming `source` (empty: the medium's) when the metadata is not "cycles" or "pbrt".
EmissionConvention emissionConvention(const Medium& medium, const std::string& source = "");

}  // namespace vdbappear
