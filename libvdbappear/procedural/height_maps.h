#pragma once
// Procedural displacement maps for the prefiltering of the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, Fig. 4.15 as models): a twill's yarns, a noise floor,
// a relief and bumps. Each is cells x cells bilinear cells over a map of width 1 (heights in the same units),
// and tiles seamlessly (opposite edges match), as Table 4.3's tiled models need.

#include "libvdbappear/surface/height_field.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vdbappear {

class WeavePattern;

// Woven fabric from its yarn geometry: warp yarns along y, weft yarns along x, `yarns` of each per
// map; each yarn a parabolic cross-section whose centre line rises over the crossings where the
// pattern puts it on top and dips under the others (smoothstep between crossings). cells must be
// a multiple of yarns.
HeightField wovenHeightMap(int cells, const WeavePattern& pattern, int yarns);

// A noise floor: a sum of 48 periodic sinusoids, 4 to 64 cycles per map with random directions and
// phases, amplitudes falling as 1/f (every wave as steep as the others, so that the fine ones shadow
// as much as the coarse), scaled to an RMS slope of 0.6.
HeightField noiseHeightMap(int cells, std::uint64_t seed);

// A relief: 8 x 8 raised squares with chamfered edges, each with an engraved ring.
HeightField reliefHeightMap(int cells);

// Bumps (the chapter's "bump" model of its ball scene, Fig. 4.15(c)): 8 x 8 round bumps, one per
// lattice cell, each a hemisphere of radius 0.3-0.45 cells flattened to 0.6 of its height, its
// centre moved up to 0.05 cells along each axis from the cell's (by the seed), so that every bump
// stays inside its cell and the map tiles.
HeightField bumpsHeightMap(int cells, std::uint64_t seed);

// "woven" (a 4-harness twill, 16 yarns), "noise", "relief" or "bumps"; throws std::invalid_argument otherwise.
HeightField heightMapByName(const std::string& name, int cells, std::uint64_t seed);
const std::vector<std::string>& heightMapNames();

}  // namespace vdbappear
