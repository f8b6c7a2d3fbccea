#pragma once
// Which exemplar fills each block of a model (docs/modularity.md): from a medium's exemplar_layout
// grid or from a JSON file. Light header: no OpenVDB.

#include <string>
#include <vector>

namespace vdbappear {

struct Medium;

struct ExemplarLayout {
  static constexpr int kEmpty = -1;
  int width = 0, height = 0, depth = 0;  // blocks along x, y, z
  std::vector<int> ids;                  // exemplar of block (i, j, k) at i + width * (j + height * k); kEmpty: none

  int at(int i, int j, int k) const { return ids[std::size_t(i + width * (j + height * k))]; }
  std::size_t blocks() const { return ids.size(); }
};

// A JSON array of sheets (z), each an array of rows (y), each an array of exemplar ids (x); a 2-D
// array is one sheet. Rows of one file have one length, sheets one row count. Throws MediumError
// naming the file.
ExemplarLayout readLayoutJson(const std::string& path);

// The medium's exemplar_layout grid: its active values at indices >= 0 (other blocks are empty).
// Throws MediumError when there is none or it is empty.
ExemplarLayout layoutOfMedium(const Medium& medium);

// Every id in 0..count-1; throws MediumError naming `where` and the first block at fault.
void checkLayoutIds(const ExemplarLayout& layout, int count, const std::string& where);

}  // namespace vdbappear
