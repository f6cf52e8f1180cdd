#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "rpArgParser.h"
#include "rpAtomicFile.h"
#include "rpLatestValue.h"

namespace fs = std::filesystem;

TEST(ArgParser, ParsesOptionsFlagsAndPositionals) {
  rp::ArgParser p("register", "test");
  p.Positional("from", "a").Positional("to", "b").Option("mode", "m", "mode", "rigid")
      .Option("target", "x,y,z", "t").Flag("verbose", "v");
  ASSERT_TRUE(p.Parse({"a.fcsv", "--mode=similarity", "b.fcsv", "--target", "1,2,3.5", "--json"}));
  EXPECT_EQ(p.Get("from"), "a.fcsv");
  EXPECT_EQ(p.Get("to"), "b.fcsv");
  EXPECT_EQ(p.Get("mode"), "similarity");
  EXPECT_TRUE(p.Json());
  EXPECT_FALSE(p.Has("verbose"));
  auto t = p.GetDoubles("target", 3);
  EXPECT_DOUBLE_EQ(t[2], 3.5);
}

TEST(ArgParser, DefaultsAndErrorsNameTheProblem) {
  rp::ArgParser p("x", "test");
  p.Positional("in", "input").Option("threshold", "mm", "t", "2.0");
  EXPECT_FALSE(p.Parse({}));
  EXPECT_NE(p.Error().find("<in>"), std::string::npos);
  EXPECT_FALSE(p.Parse({"a", "--bogus"}));
  EXPECT_NE(p.Error().find("--bogus"), std::string::npos);
  EXPECT_FALSE(p.Parse({"a", "--threshold"}));
  EXPECT_NE(p.Error().find("needs a value"), std::string::npos);
  EXPECT_FALSE(p.Parse({"a", "b"}));
  ASSERT_TRUE(p.Parse({"a"}));
  EXPECT_DOUBLE_EQ(p.GetDouble("threshold"), 2.0);
  ASSERT_TRUE(p.Parse({"a", "--threshold", "abc"}));
  EXPECT_THROW(p.GetDouble("threshold"), std::invalid_argument);
  EXPECT_FALSE(p.Parse({"--help"}));
  EXPECT_TRUE(p.HelpRequested());
  EXPECT_NE(p.Usage().find("--threshold <mm>"), std::string::npos);
}

TEST(AtomicFile, FailedWriteKeepsTheLastGoodFile) {
  const fs::path dir = fs::path(ROBOPLAN_TEST_OUTPUT_DIR) / "atomic";
  fs::create_directories(dir);
  const std::string path = (dir / "scene.json").string();
  std::string error;
  ASSERT_TRUE(rp::WriteFileAtomically(path, "good", error)) << error;
  const bool ok = rp::WriteAtomicallyWith(
      path,
      [](const std::string& temp, std::string& err) {
        rp::WriteFileAtomically(temp, "half-written", err);
        err = "simulated failure";
        return false;
      },
      error);
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find("simulated failure"), std::string::npos);
  std::string contents;
  ASSERT_TRUE(rp::ReadFile(path, contents, error));
  EXPECT_EQ(contents, "good");
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "scene.json");
}

struct Pose {
  double Values[16];
  uint64_t Frame;
};

TEST(LatestValue, ReaderNeverSeesATornValue) {
  rp::LatestValue<Pose> exchange;
  Pose p{};
  EXPECT_EQ(exchange.Read(p), 0u);
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    Pose w{};
    for (uint64_t f = 1; f <= 200000; ++f) {
      w.Frame = f;
      for (double& v : w.Values) v = static_cast<double>(f);
      exchange.Publish(w);
    }
    stop = true;
  });
  uint64_t lastFrame = 0, reads = 0;
  while (!stop || reads == 0) {
    Pose r{};
    if (exchange.Read(r)) {
      for (double v : r.Values) ASSERT_EQ(v, static_cast<double>(r.Frame));
      ASSERT_GE(r.Frame, lastFrame);
      lastFrame = r.Frame;
      ++reads;
    }
  }
  writer.join();
  EXPECT_EQ(exchange.PublishCount(), 200000u);
}
