#pragma once
// An int read from a JSON value (checkpoints, metadata, layouts). nlohmann's get<int>() converts
// a floating-point value out of int's range with undefined behaviour and a fraction or a wider
// integer silently; this refuses all three (found by the checkpoint fuzz harness, docs/reliability.md).

#include <nlohmann/json.hpp>

#include <limits>
#include <stdexcept>
#include <string>

namespace vdbappear {

// Throws std::invalid_argument "WHAT: expected an integer, got VALUE".
inline int intOf(const nlohmann::json& value, const std::string& what) {
  if (value.is_number_integer()) {
    const auto wide = value.get<std::int64_t>();
    if (value.is_number_unsigned() ? value.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max())
                                   : wide >= std::numeric_limits<int>::min() && wide <= std::numeric_limits<int>::max())
      return int(wide);
  }
  throw std::invalid_argument(what + ": expected an integer, got " + value.dump());
}

}  // namespace vdbappear
