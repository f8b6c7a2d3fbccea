#pragma once
// A medium held for rendering in its compact form (docs/rendering.md, "The render's medium in
// memory"): the density as read (float leaves), and the albedo and SGGX S of each active density
// voxel in one 18-byte record (medium/compact_attributes.h), instead of the 36 bytes the float grids
// hold for every voxel of every leaf. Read from a file piece by piece (io/medium_slabs.h), so that the
// float grids are never whole in memory. Light header: no OpenVDB.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

class CompactAttributes;
class ProgressBar;

struct CompactMedium {
  MediumPtr medium;  // the density and the file's metadata; no albedo or SGGX grids
  std::shared_ptr<const CompactAttributes> attributes;  // null where the medium has neither
  int pieces = 1;                                        // read in this many pieces
  std::vector<std::string> notes;                        // the reader's, as readMedium gives them
  std::uint64_t density_bytes = 0, attribute_bytes = 0;  // in memory
};

// Why a medium cannot take the compact form, or nullopt: the form holds density, albedo and SGGX S;
// a medium with lobes, a phase table, an hg_g grid, clusters, emission or an instanced layout is
// rendered from its grids, as is a density with active tiles.
std::optional<std::string> whyNotCompact(const Medium& medium);

// The compact form of a medium read whole (its albedo and SGGX grids are dropped from the copy; the
// density is shared). nullopt, with the reason in why_not, as whyNotCompact.
std::optional<CompactMedium> compactMedium(const MediumPtr& medium, std::string* why_not);

// Reads `path` piece by piece (io/medium_slabs.h; pieces of at most `memory_bytes`) into the compact
// form: each piece is checked as readMedium checks a medium, its records made and its density leaves
// kept. nullopt, with the reason in why_not, where the file must be read whole (as MediumSlabs says)
// or the medium cannot take the compact form (whyNotCompact). MediumError as readMedium gives it.
std::optional<CompactMedium> readCompactMedium(const std::string& path, const GridMapping& mapping,
                                               std::uint64_t memory_bytes, std::string* why_not,
                                               ProgressBar* progress = nullptr);

}  // namespace vdbappear
