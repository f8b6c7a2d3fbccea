#include "libvdbappear/io/emission_convention.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

namespace vdbappear {

std::optional<EmissionConvention> parseEmissionConvention(const std::string& name) {
  if (name == "cycles") return EmissionConvention::kCycles;
  if (name == "pbrt") return EmissionConvention::kPbrt;
  return std::nullopt;
}

const char* emissionConventionName(EmissionConvention convention) {
  return convention == EmissionConvention::kCycles ? "cycles" : "pbrt";
}

EmissionConvention emissionConvention(const Medium& medium, const std::string& source) {
  const std::string& file = source.empty() ? medium.source : source;
  const openvdb::Metadata::ConstPtr value = medium.metadata[metadata_names::kEmissionConvention];
  if (!value) return EmissionConvention::kCycles;
  const auto text = medium.metadata.getMetadata<openvdb::StringMetadata>(metadata_names::kEmissionConvention);
  if (!text) throw MediumError(fmt::format("{}: metadata '{}' is not a string", file, metadata_names::kEmissionConvention));
  if (const auto convention = parseEmissionConvention(text->value())) return *convention;
  throw MediumError(fmt::format("{}: metadata '{}' = '{}': expected cycles or pbrt", file,
                                metadata_names::kEmissionConvention, text->value()));
}

}  // namespace vdbappear
