#pragma once
// Where a test writes its files: ROBOPLAN_TEST_OUTPUT_DIR (build/Testing/Temporary/<test>)/name,
// emptied first so a run never reads what an earlier run left.
#include <filesystem>
#include <string>

namespace rptest {

inline std::filesystem::path TestDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(ROBOPLAN_TEST_OUTPUT_DIR) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace rptest
