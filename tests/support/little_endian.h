#pragma once
// Bytes as files store them (little-endian), for tests that build or damage file headers by hand.

#include <cstdint>
#include <string>

namespace vdbappear::test {

inline std::string littleEndian32(std::uint32_t value) { return std::string(reinterpret_cast<const char*>(&value), 4); }

}  // namespace vdbappear::test
