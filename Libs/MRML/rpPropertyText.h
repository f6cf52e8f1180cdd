#pragma once
// Numbers in node properties (scene files, MRML attributes of our fields, .mrk.json attributes):
// the shortest text that reads back to the same double, without the C locale (a viewer in a
// locale with decimal commas writes and reads the same files), and a strict reader.
#include <string>
#include <vector>

namespace rp {

/// "2.5", "0.1", "1e-07": std::to_chars' shortest round-trip form.
std::string FormatPropertyNumber(double value);
/// Numbers separated by one space.
std::string FormatPropertyNumbers(const double* values, int count);
/// Reads finite numbers separated by spaces. False unless the whole text is numbers and, when
/// `count` > 0, exactly `count` of them.
bool ParsePropertyNumbers(const std::string& text, std::vector<double>& values, size_t count = 0);
/// One finite number.
bool ParsePropertyNumber(const std::string& text, double& value);

}  // namespace rp
