#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <thread>

#include "rpArgParser.h"
#include "rpAtomicFile.h"
#include "rpCLIDescriptors.h"
#include "rpLatestValue.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"

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

// Every `roboplan <command>` parses through ParseCommand: run, help (exit 0, usage on out) or a
// bad argument (exit 2, "roboplan <command>: <error>" and the usage on err).
TEST(ArgParser, ParseCommandGivesTheExitCodeAndPrintsWhereItBelongs) {
  rp::ArgParser p("thing", "test");
  p.Positional("in", "input");
  std::ostringstream out, err;
  EXPECT_FALSE(p.ParseCommand({"a"}, out, err).has_value());
  EXPECT_EQ(out.str() + err.str(), "");
  EXPECT_EQ(p.ParseCommand({"--help"}, out, err), 0);
  EXPECT_EQ(out.str().rfind("usage: roboplan thing", 0), 0u) << out.str();
  EXPECT_EQ(err.str(), "");
  out.str("");
  EXPECT_EQ(p.ParseCommand({"a", "--bogus"}, out, err), 2);
  EXPECT_EQ(out.str(), "");
  EXPECT_EQ(err.str().rfind("roboplan thing: ", 0), 0u) << err.str();
  EXPECT_NE(err.str().find("--bogus"), std::string::npos);
  EXPECT_NE(err.str().find("usage: roboplan thing"), std::string::npos);
}

// A command declared with types, ranges, choices and files, as `register-volumes` is.
rp::ArgParser TypedParser() {
  rp::ArgParser p("typed", "Typed test command & <friends>.");
  p.Positional("fixed", "fixed volume").Input(rp::FileKind::Image, {".nrrd", ".nii.gz"})
      .Option("out", "transform", "output").Output(rp::FileKind::Transform, {".tfm"}).Required()
      .Option("mode", "rigid|similarity", "mode", "rigid").OneOf()
      .Option("iterations", "n", "iterations", "200").Integer().AtLeast(1).AtMost(1000)
      .Option("sampling", "fraction", "sampling", "0.1").Number().GreaterThan(0).AtMost(1)
      .Option("seed", "x,y,z", "seed point").Point().Repeatable()
      .Option("levels", "f1,f2", "levels", "4,2,1").Integers().AtLeast(1)
      .Flag("fill-holes", "fill holes");
  return p;
}

TEST(ArgParser, DeclaredTypesRangesChoicesAndRequiredOptionsAreChecked) {
  rp::ArgParser p = TypedParser();
  ASSERT_TRUE(p.Parse({"ct.nrrd", "--out", "a.tfm", "--iterations", "5", "--seed", "1,2,3", "--seed=4,5,6"}))
      << p.Error();
  EXPECT_EQ(p.GetAll("seed").size(), 2u);
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"ct.nrrd"}, "--out <transform> is required"},
      {{"ct.nrrd", "--out", "a.tfm", "--iterations", "0"}, "--iterations must be >= 1"},
      {{"ct.nrrd", "--out", "a.tfm", "--iterations", "2.5"}, "'2.5' is not an integer"},
      {{"ct.nrrd", "--out", "a.tfm", "--sampling", "0"}, "--sampling must be > 0 and <= 1 (got 0)"},
      {{"ct.nrrd", "--out", "a.tfm", "--sampling", "nan"}, "is not a number"},
      {{"ct.nrrd", "--out", "a.tfm", "--mode", "affine"}, "'affine' is not one of rigid|similarity"},
      {{"ct.nrrd", "--out", "a.tfm", "--seed", "1,2"}, "is not a point x,y,z"},
      {{"ct.nrrd", "--out", "a.tfm", "--levels", "4,0"}, "--levels must be >= 1 (got 0)"},
      {{"ct.nrrd", "--out", "a.tfm", "--levels", ""}, "--levels needs comma-separated integers"},
  };
  for (const auto& [args, message] : bad) {
    EXPECT_FALSE(p.Parse(args));
    EXPECT_NE(p.Error().find(message), std::string::npos) << p.Error() << " should say " << message;
  }
}

TEST(ArgParser, AcceptsSlicerUnderscoreSpellingOfLongFlags) {
  rp::ArgParser p = TypedParser();
  ASSERT_TRUE(p.Parse({"ct.nrrd", "--out", "a.tfm", "--fill_holes"})) << p.Error();
  EXPECT_TRUE(p.Has("fill-holes"));
}

TEST(ArgParser, SlicerXMLDescriptorCarriesTheDeclarations) {
  rp::ArgParser p = TypedParser();
  EXPECT_FALSE(p.Parse({"--xml"}));
  ASSERT_TRUE(p.HelpRequested());
  const std::string xml = p.Usage();
  for (const std::string expected :
       {"<executable>", "<title>RoboPlan typed</title>",
        "<description>Typed test command &amp; &lt;friends&gt;.</description>",
        "<image type=\"scalar\" fileExtensions=\".nrrd,.nii.gz\">", "<index>0</index>",
        "<transform type=\"linear\" fileExtensions=\".tfm\">", "<channel>output</channel>",
        "<string-enumeration>", "<element>similarity</element>", "<integer>", "<minimum>1</minimum>",
        "<maximum>1000</maximum>", "<point multiple=\"true\" coordinateSystem=\"ras\">", "<integer-vector>",
        "<boolean>", "<longflag>fill_holes</longflag>", "<name>fill_holes</name>"}) {
    EXPECT_NE(xml.find(expected), std::string::npos) << expected << " missing in\n" << xml;
  }
  EXPECT_EQ(xml.find("json"), std::string::npos) << "the built-in --json is not a parameter";
}

TEST(ArgParser, BoutiquesDescriptorCarriesTheDeclarations) {
  rp::ArgParser p = TypedParser();
  EXPECT_FALSE(p.Parse({"--boutiques"}));
  const std::string text = p.Usage();
  for (const std::string expected :
       {"\"schema-version\": \"0.5\"", "\"command-line\": \"roboplan typed [FIXED] [OUT] [MODE] [ITERATIONS]",
        "\"value-choices\": [", "\"exclusive-minimum\": true", "\"list-separator\": \" --seed \"",
        "\"path-template\": \"[OUT]\"", "\"command-line-flag\": \"--fill-holes\"", "\"type\": \"Flag\""}) {
    EXPECT_NE(text.find(expected), std::string::npos) << expected << " missing in\n" << text;
  }
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

// LPS <-> RAS against matrices worked out by hand. S = diag(-1, -1, 1).
TEST(LPSRAS, PointsGridsAndTransforms) {
  double p[3] = {10.0, -20.0, 30.0};
  rp::FlipLPSRASPoint(p);
  EXPECT_EQ(p[0], -10.0);
  EXPECT_EQ(p[1], 20.0);
  EXPECT_EQ(p[2], 30.0);

  // The GE CT of shared/data: IJK-to-LPS diag(0.81, 0.81, 1), origin (-235.2, -226.8, -128.69)
  // is IJK-to-RAS diag(-0.81, -0.81, 1), origin (235.2, 226.8, -128.69).
  double grid[16] = {0.81, 0, 0, -235.2, 0, 0.81, 0, -226.8, 0, 0, 1, -128.69, 0, 0, 0, 1};
  rp::FlipLPSRASIndexToSpace(grid);
  const double gridRAS[16] = {-0.81, 0, 0, 235.2, 0, -0.81, 0, 226.8, 0, 0, 1, -128.69, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) EXPECT_EQ(grid[i] + 0.0, gridRAS[i]) << i;  // + 0.0: -0 == 0

  // A rotation by 30 degrees about x in LPS is a rotation by -30 degrees about x in RAS; a
  // rotation about z is the same in both; a translation (1, 2, 3) becomes (-1, -2, 3).
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  double rx[16] = {1, 0, 0, 1, 0, c, -s, 2, 0, s, c, 3, 0, 0, 0, 1};
  rp::FlipLPSRASTransform(rx);
  const double rxRAS[16] = {1, 0, 0, -1, 0, c, s, -2, 0, -s, c, 3, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) EXPECT_DOUBLE_EQ(rx[i], rxRAS[i]) << i;
  double rz[16] = {c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const double rzCopy[16] = {c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  rp::FlipLPSRASTransform(rz);
  for (int i = 0; i < 16; ++i) EXPECT_DOUBLE_EQ(rz[i], rzCopy[i]) << i;

  // Consistency: flipping the transform then the point = flipping the transformed point.
  double m[16] = {0.2, -0.9, 0.3, 4, 0.7, 0.1, -0.6, -5, 0.5, 0.4, 0.8, 6, 0, 0, 0, 1};
  const double q[3] = {1.5, -2.5, 7.0};
  double mq[3];
  for (int r = 0; r < 3; ++r) mq[r] = m[4 * r] * q[0] + m[4 * r + 1] * q[1] + m[4 * r + 2] * q[2] + m[4 * r + 3];
  rp::FlipLPSRASPoint(mq);
  rp::FlipLPSRASTransform(m);
  double qf[3] = {q[0], q[1], q[2]};
  rp::FlipLPSRASPoint(qf);
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(m[4 * r] * qf[0] + m[4 * r + 1] * qf[1] + m[4 * r + 2] * qf[2] + m[4 * r + 3], mq[r], 1e-12);

  double sm[16];
  rp::LPSRASMatrix(sm);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(sm[i], i == 0 || i == 5 ? -1.0 : (i == 10 || i == 15 ? 1.0 : 0.0)) << i;
}

TEST(MemoryBudget, RefusesWhatCannotFitBeforeAllocating) {
  std::string error;
  const int64_t huge[3] = {100000, 100000, 100000};
  EXPECT_FALSE(rp::CheckImageFitsInMemory(huge, 1.0, "big.nrrd", error, 1.0, uint64_t(24e9)));
  EXPECT_NE(error.find("big.nrrd: 100000 x 100000 x 100000 voxels of 1 byte would need 1e+06 GB"), std::string::npos)
      << error;
  EXPECT_NE(error.find("24.0 GB of memory are available"), std::string::npos) << error;
  const int64_t overflow[3] = {int64_t(1) << 40, int64_t(1) << 40, 4};
  EXPECT_FALSE(rp::CheckImageFitsInMemory(overflow, 4.0, "x", error));
  EXPECT_NE(error.find("more than any computer can address"), std::string::npos) << error;
  const int64_t ct[3] = {512, 512, 300};
  EXPECT_TRUE(rp::CheckImageFitsInMemory(ct, 2.0, "ct", error, 2.0, uint64_t(1e9)));
  EXPECT_FALSE(rp::CheckImageFitsInMemory(ct, 2.0, "ct", error, 2.0, uint64_t(300e6)));
  EXPECT_NE(error.find("would need 315 MB; only 300 MB"), std::string::npos) << error;
  const int64_t negative[3] = {10, -1, 10};
  EXPECT_FALSE(rp::CheckImageFitsInMemory(negative, 2.0, "bad", error));
  EXPECT_NE(error.find("invalid size"), std::string::npos) << error;
  EXPECT_GT(rp::AvailableMemoryBytes(), uint64_t(0));
}
