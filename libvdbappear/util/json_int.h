#pragma once
// An integer read from a JSON value (scenes, checkpoints, metadata, layouts). nlohmann's get<T>()
// converts a floating-point value out of T's range with undefined behaviour, and a fraction or a
// wider integer silently; this refuses all three (found by the checkpoint and scene fuzz harnesses,
// docs/reliability.md).

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace vdbappear {

// A JSON integer within T's range; else throws std::invalid_argument
// "WHAT: expected an integer in MIN..MAX, got VALUE" (without "WHAT: " when it is empty).
template <typename T>
T integerOf(const nlohmann::json& value, const std::string& what) {
  static_assert(std::is_integral_v<T> && sizeof(T) <= 8, "an integer of at most 64 bits");
  using Limits = std::numeric_limits<T>;
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v <= std::uint64_t(Limits::max())) return T(v);
  } else if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if constexpr (std::is_signed_v<T>) {
      if (v >= std::int64_t(Limits::min()) && v <= std::int64_t(Limits::max())) return T(v);
    } else {
      if (v >= 0 && std::uint64_t(v) <= std::uint64_t(Limits::max())) return T(v);
    }
  }
  throw std::invalid_argument((what.empty() ? "" : what + ": ") + "expected an integer in " + std::to_string(Limits::min()) + ".." +
                              std::to_string(Limits::max()) + ", got " + value.dump());
}

// Throws std::invalid_argument "WHAT: expected an integer in ..., got VALUE".
inline int intOf(const nlohmann::json& value, const std::string& what) { return integerOf<int>(value, what); }

}  // namespace vdbappear
