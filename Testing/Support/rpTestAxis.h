#pragma once
// A planned axis for tests (entry → target), failing the test when the two points cannot make one.
#include <gtest/gtest.h>

#include <string>

#include "rpTrajectoryAxis.h"

namespace rptest {

inline rp::TrajectoryAxis Axis(const rp::Vec3& entry, const rp::Vec3& target) {
  rp::TrajectoryAxis axis;
  std::string error;
  EXPECT_TRUE(rp::TrajectoryAxis::Make(entry, target, axis, error)) << error;
  return axis;
}

}  // namespace rptest
