#pragma once
// Tests that read ../shared/data (real files written by other tools; see its README) use
//     RP_REQUIRE_SHARED_DATA("dicom/ct-3slice");
// at the top of the test: when the path is absent (a GitHub clone has no ../shared) the test is
// reported SKIPPED with the missing path; when it is there the test runs. With
// ROBOPLAN_REQUIRE_SHARED_DATA=1 in the environment (.ci/run sets it when ../shared/data exists)
// a missing path FAILS instead: data that is there must be used, not silently skipped.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace rptest {

/// ROBOPLAN_SHARED_DATA_DIR/relative (an absolute path is taken as it is).
inline std::string SharedDataPath(const std::string& relative) {
  return !relative.empty() && relative[0] == '/' ? relative : std::string(ROBOPLAN_SHARED_DATA_DIR) + "/" + relative;
}

inline bool SharedDataRequired() {
  const char* value = std::getenv("ROBOPLAN_REQUIRE_SHARED_DATA");
  return value != nullptr && *value != '\0' && std::string(value) != "0";
}

}  // namespace rptest

#define RP_REQUIRE_SHARED_DATA(relative)                                                                   \
  do {                                                                                                     \
    const std::string rpSharedDataPath_ = ::rptest::SharedDataPath(relative);                              \
    if (!std::filesystem::exists(rpSharedDataPath_)) {                                                     \
      if (::rptest::SharedDataRequired())                                                                  \
        FAIL() << "shared data missing although ROBOPLAN_REQUIRE_SHARED_DATA is set: " << rpSharedDataPath_; \
      GTEST_SKIP() << "shared data absent: " << rpSharedDataPath_                                          \
                   << " (put ../shared/data beside the repository to run this test)";                      \
    }                                                                                                      \
  } while (0)
