#pragma once
// Why OpenVDB could not read a file or stream, as the error line of a reader says it.

#include <exception>
#include <string>

namespace vdbappear {

// The exception's message; a read that failed inside OpenVDB's readers (which throw
// std::ios_base::failure there, io/vdb_record_guard.cpp) says that the data ended early.
std::string vdbReadError(const std::exception& error);

}  // namespace vdbappear
