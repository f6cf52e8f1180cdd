#pragma once
// Small text helpers the readers of headers, configurations and addresses share.
#include <string>

namespace rp {

/// `text` without the white space (std::isspace) at its start and end.
std::string Trim(const std::string& text);
/// `text` in lower case (ASCII letters; other bytes unchanged).
std::string Lower(std::string text);
/// `value` with `digits` decimals (printf's "%.*f": "nan", "inf" as it writes them).
std::string Fixed(double value, int digits);

}  // namespace rp
