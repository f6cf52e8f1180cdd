// libFuzzer target: Slicer's .mrk.json and .fcsv parsers on arbitrary bytes (both, whatever the
// input), and the writers on what they parsed (written files must parse back, same count).
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "rpMarkupsFormat.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const double color[3] = {1, 0, 0};
  std::vector<rp::ControlPoint> points, again;
  if (rp::ParseMarkupsJson(text, "fuzz.mrk.json", points, error)) {
    if (!rp::ParseMarkupsJson(rp::FormatMarkupsJson(points, color), "again.mrk.json", again, error)) std::abort();
    if (again.size() != points.size()) std::abort();
  }
  points.clear();
  again.clear();
  if (rp::ParseFcsv(text, "fuzz.fcsv", points, error)) {
    if (!rp::ParseFcsv(rp::FormatFcsv(points), "again.fcsv", again, error)) std::abort();
    if (again.size() != points.size()) std::abort();
  }
  return 0;
}
