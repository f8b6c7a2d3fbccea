#pragma once
// A medium's identity by content, for caches, checkpoints and provenance. Light header: no OpenVDB.

#include <string>

namespace vdbappear {

struct Medium;

// XXH3-128 (hex) of a medium's content: every grid's name, transform and active values with their
// coordinates, in tree order. Identifies a medium read from a stream, where no file bytes are left
// to hash (checkpoints compare it), and the exemplar set a stacked medium came from.
std::string mediumContentHash(const Medium& medium);

}  // namespace vdbappear
