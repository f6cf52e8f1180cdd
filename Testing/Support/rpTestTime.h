#pragma once
// How long a test waits for what another thread does (a display thread's mesh, a servo moving the
// burr): the plain build's seconds times ROBOPLAN_TEST_TIME_FACTOR, which the sanitizer builds set
// to their ctest timeout factor (RoboPlanMacros.cmake: TSan runs our code several times slower).
// Not for limits a test measures (latencies, rates): those stay what they are.
#include <cstdlib>

namespace rptest {

inline double WaitSeconds(double seconds) {
  const char* text = std::getenv("ROBOPLAN_TEST_TIME_FACTOR");
  const double factor = text ? std::atof(text) : 1.0;
  return factor > 1.0 ? seconds * factor : seconds;
}

}  // namespace rptest
