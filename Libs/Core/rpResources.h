#pragma once
// Where Resources/ (tissue materials, tool definitions, icons) is: $ROBOPLAN_RESOURCES_DIR, then
// the install tree (<prefix>/share/roboplan/Resources beside bin/), then the source tree the
// program was built from.
#include <string>

namespace rp {

std::string ResourcesDirectory();
/// ResourcesDirectory() + "/" + relative.
std::string ResourcePath(const std::string& relative);

}  // namespace rp
