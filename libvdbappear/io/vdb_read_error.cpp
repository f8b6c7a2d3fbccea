#include "libvdbappear/io/vdb_read_error.h"

#include <ios>

namespace vdbappear {

std::string vdbReadError(const std::exception& error) {
  if (dynamic_cast<const std::ios_base::failure*>(&error) != nullptr)
    return "it ends before the data it describes: truncated or damaged";
  return error.what();
}

}  // namespace vdbappear
