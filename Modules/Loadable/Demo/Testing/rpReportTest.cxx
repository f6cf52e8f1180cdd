#include <gtest/gtest.h>

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "rpReport.h"
#include "rpStageRunner.h"

TEST(Report, FiguresAreScoredAgainstTheirTargets) {
  rp::Report report("test");
  report.AddFigureBelow("Registration", "RMS error", 0.4, "mm", 1.0);
  report.AddFigureBelow("Meshing", "volume error", 1.5, "%", 1.0);
  report.AddFigureAbove("Tracking", "rate", 59.0, "Hz", 55.0);
  report.AddNotScored("Segmentation", "Dice", "no ground truth for a user's CT");
  ASSERT_EQ(report.GetFigures().size(), 4u);
  EXPECT_EQ(report.GetFigures()[0].Result, rp::Report::Verdict::Pass);
  EXPECT_EQ(report.GetFigures()[1].Result, rp::Report::Verdict::Fail);
  EXPECT_EQ(report.GetFigures()[2].Result, rp::Report::Verdict::Pass);
  EXPECT_EQ(report.GetFigures()[3].Result, rp::Report::Verdict::NotScored);
  EXPECT_EQ(report.CountFailed(), 1);
  const std::string html = report.ToHtml();
  EXPECT_NE(html.find("no ground truth for a user's CT"), std::string::npos);
  EXPECT_NE(html.find("not scored"), std::string::npos);
  EXPECT_NE(html.find("FAIL"), std::string::npos);
  const std::string json = report.ToJson();
  EXPECT_NE(json.find("\"result\": \"fail\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"value\": null"), std::string::npos) << json;  // the figure not measured
  EXPECT_NE(json.find("\"value\": 0.4"), std::string::npos) << json;
}

TEST(Report, JsonSectionsSitBesideTheFigures) {
  rp::Report report("test");
  report.SetJsonSection("executions", R"([{"name": "free hand", "tipOffsetMm": 1.25}])");
  report.SetJsonSection("executions", R"([{"name": "guided", "tipOffsetMm": 0.25}])");  // replaces
  report.SetJsonSection("broken", "{not json");
  const nlohmann::json doc = nlohmann::json::parse(report.ToJson());
  ASSERT_EQ(doc["executions"].size(), 1u);
  EXPECT_EQ(doc["executions"][0]["name"], "guided");
  EXPECT_EQ(doc["executions"][0]["tipOffsetMm"].get<double>(), 0.25);
  EXPECT_EQ(doc["broken"], "{not json");
  EXPECT_TRUE(doc["figures"].is_array());
}

TEST(StageRunner, StopsAtTheFirstFailureAndRecordsIt) {
  rp::Report report("test");
  rp::StageRunner runner(report, 3, true);
  int ran = 0;
  EXPECT_TRUE(runner.Run("one", [&] { ++ran; }));
  EXPECT_FALSE(runner.Run("two", [&] { throw std::runtime_error("the tracker did not answer"); }));
  EXPECT_FALSE(runner.Run("three", [&] { ++ran; }));
  EXPECT_EQ(ran, 1);
  EXPECT_TRUE(runner.Failed());
  EXPECT_EQ(runner.FailureMessage(), "two: the tracker did not answer");
  ASSERT_EQ(report.GetStages().size(), 2u);
  EXPECT_FALSE(report.GetStages()[1].Ok);
}
