#pragma once

#include <stdexcept>
#include <string>

namespace vdbappear {

// Bad input or output: the message names the file (or "stdin"/"stdout") and, where one is at
// fault, the grid. Tools print it as is and exit with a non-zero status.
class MediumError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vdbappear
