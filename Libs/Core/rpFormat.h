#pragma once
// printf-style formatting into a std::string: the numbers of reports, read-outs and errors.
#include <string>

namespace rp {

/// What std::snprintf(format, ...) writes, whole (no length limit). The compiler checks the
/// arguments against the format.
std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rp
