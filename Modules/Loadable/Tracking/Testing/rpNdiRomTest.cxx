// NDI tool definitions (.rom) against the five real files of PlusLibData (written by NDI's tool
// software and a lab): the checksum of each, the markers of NDI's published passive tools, the
// date fields, and the writer giving every file back byte for byte; then our own generated
// ROMs, corrupted ones, and `roboplan tool-info`.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpDeviceCommands.h"
#include "rpNdiRom.h"
#include "rpSharedData.h"
#include "rpToolDefinition.h"

using namespace rp;

namespace {
const std::string kRoms = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data/ConfigFiles/NdiToolDefinitions/";

struct RealRom {
  const char* File;
  int Markers;
  const char* Part;
  int Year, Month, Day;
  std::vector<rom::Vec3> Geometry;  // NDI's published marker coordinates (mm), empty: not published
};

// NDI's passive tools: 8700339 (tool), 8700340 (stylus), 8700449 (reference) of the Polaris
// starter kit, 8700248 (three markers on a line: a 5-DoF probe); the Robarts stylus is custom.
const std::vector<RealRom>& RealRoms() {
  static const std::vector<RealRom> kRealRoms = {
      {"8700248.rom", 3, "8700248", 2001, 4, 10, {{0, 0, 0}, {0, 0, 50}, {0, 0, 105}}},
      {"8700339.rom", 4, "8700339", 2005, 1, 6, {{0, 0, 0}, {0, 28.59, 41.02}, {0, 0, 88}, {0, -44.32, 40.45}}},
      {"8700340.rom", 4, "8700340", 2005, 1, 10, {{0, 0, 0}, {0, 0, 50}, {0, 25, 100}, {0, -25, 135}}},
      {"8700449.rom", 4, "8700449", 2006, 7, 3, {{0, 0, 0}, {0, 47.38, 28.99}, {0, 0, 89.1}, {0, -35.36, 35.36}}},
      {"P4_Camera_Calib_Stylus.rom", 4, "CalibStylus", 2018, 5, 28, {}},
  };
  return kRealRoms;
}
}  // namespace

TEST(NdiRomFiles, RealRomsReadWithTheirChecksumMarkersAndDates) {
  RP_REQUIRE_SHARED_DATA(kRoms);
  for (const RealRom& real : RealRoms()) {
    SCOPED_TRACE(real.File);
    std::vector<uint8_t> bytes;
    const rom::Definition d = rom::ReadFile(kRoms + real.File, &bytes);
    ASSERT_EQ(bytes.size(), rom::Size);
    EXPECT_EQ(d.Checksum, rom::ComputeChecksum(bytes.data(), bytes.size()));
    EXPECT_EQ(static_cast<int>(d.Markers.size()), real.Markers);
    EXPECT_EQ(d.PartNumber, real.Part);
    EXPECT_EQ(d.Year, real.Year);
    EXPECT_EQ(d.Month, real.Month);
    EXPECT_EQ(d.Day, real.Day);
    EXPECT_EQ(d.MarkerType, 41);  // passive spheres
    EXPECT_GE(d.MinimumMarkers, 3);
    EXPECT_LE(d.MinimumMarkers, real.Markers);
    for (size_t m = 0; m < real.Geometry.size(); ++m)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(d.Markers[m][static_cast<size_t>(k)], real.Geometry[m][static_cast<size_t>(k)], 1e-4);
    for (const auto& n : d.Normals) {  // unit normals, or none (8700248)
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      EXPECT_TRUE(std::abs(length - 1) < 1e-5 || length == 0) << length;
    }
  }
}

TEST(NdiRomFiles, CustomStylusMarkersLieInThePlaneTheirNormalsFace) {
  RP_REQUIRE_SHARED_DATA(kRoms);
  // The Robarts stylus: four markers about their centroid, one normal for all: the markers must
  // lie in a plane perpendicular to it (a layout that read the wrong offsets would not).
  const rom::Definition d = rom::ReadFile(kRoms + "P4_Camera_Calib_Stylus.rom");
  ASSERT_EQ(d.Markers.size(), 4u);
  const auto& n = d.Normals[0];
  double c[3] = {0, 0, 0};
  for (const auto& p : d.Markers)
    for (int k = 0; k < 3; ++k) c[k] += p[static_cast<size_t>(k)] / 4;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.0, 0.01);
  for (const auto& p : d.Markers) {
    const double along = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
    EXPECT_LT(std::abs(along), 3.0) << "marker off the plane by " << along << " mm";
  }
  ASSERT_EQ(d.FaceNormals.size(), 1u);
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(d.FaceNormals[0][static_cast<size_t>(k)], n[static_cast<size_t>(k)]);
}

TEST(NdiRomFiles, WritingTheFieldsGivesEachRealFileBackByteForByte) {
  RP_REQUIRE_SHARED_DATA(kRoms);
  for (const RealRom& real : RealRoms()) {
    SCOPED_TRACE(real.File);
    std::vector<uint8_t> bytes;
    const rom::Definition d = rom::ReadFile(kRoms + real.File, &bytes);
    const std::vector<uint8_t> written = rom::Write(d);
    ASSERT_EQ(written.size(), bytes.size());
    for (size_t i = 0; i < bytes.size(); ++i) ASSERT_EQ(written[i], bytes[i]) << "byte " << i;
  }
}

TEST(NdiRomFiles, GeneratedToolsPassTheSameChecksumAndKeepTheirMarkers) {
  for (const char* name : {"Stylus", "Reference", "Pointer"}) {
    SCOPED_TRACE(name);
    const ToolDefinition tool = ReadToolDefinition(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/" + name + ".json");
    rom::Definition d;
    std::string error;
    ASSERT_TRUE(rom::Read(tool.Rom.data(), tool.Rom.size(), d, error)) << error;
    EXPECT_EQ(d.PartNumber, tool.PartNumber);
    ASSERT_EQ(d.Markers.size(), tool.Markers.size());
    for (size_t m = 0; m < d.Markers.size(); ++m)
      for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(d.Markers[m][static_cast<size_t>(k)], tool.Markers[m][static_cast<size_t>(k)]);
    // The committed Resources/Tools/<name>.rom is what the writer makes of the .json.
    const std::vector<uint8_t> committed = ReadBinaryFile(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/" + name + ".rom");
    EXPECT_EQ(committed, tool.Rom);
  }
}

TEST(NdiRomFiles, CorruptedOrCutDefinitionsAreRefusedNamingTheProblem) {
  const std::vector<uint8_t> good = rom::Build("RP-TEST", {{0, 0, 0}, {0, 50, 0}, {40, 0, 0}});
  rom::Definition d;
  std::string error;
  ASSERT_TRUE(rom::Read(good.data(), good.size(), d, error)) << error;
  std::vector<uint8_t> bad = good;
  bad[100] ^= 0x10;
  EXPECT_FALSE(rom::Read(bad.data(), bad.size(), d, error));
  EXPECT_NE(error.find("checksum mismatch"), std::string::npos) << error;
  EXPECT_FALSE(rom::Read(good.data(), 200, d, error));
  bad = good;
  bad[28] = 0;  // no markers, checksum fixed
  const uint16_t sum = rom::ComputeChecksum(bad.data(), bad.size());
  bad[4] = static_cast<uint8_t>(sum);
  bad[5] = static_cast<uint8_t>(sum >> 8);
  EXPECT_FALSE(rom::Read(bad.data(), bad.size(), d, error));
  EXPECT_NE(error.find("marker count 0"), std::string::npos) << error;
  // Random damage never crashes and is refused unless the checksum still matches by chance.
  std::mt19937 rng(7);
  int refused = 0;
  for (int i = 0; i < 5000; ++i) {
    std::vector<uint8_t> m = good;
    m.resize(std::uniform_int_distribution<size_t>(0, 800)(rng), 0);
    for (int k = 0; k < 4 && !m.empty(); ++k) m[std::uniform_int_distribution<size_t>(0, m.size() - 1)(rng)] ^= static_cast<uint8_t>(rng());
    if (!rom::Read(m.data(), m.size(), d, error)) ++refused;
  }
  EXPECT_GT(refused, 4900);
}

TEST(NdiRomFiles, ToolInfoPrintsTheDefinitionAsJson) {
  RP_REQUIRE_SHARED_DATA(kRoms);
  std::ostringstream out, err;
  ASSERT_EQ(RunToolInfoCommand({kRoms + "8700340.rom", "--json"}, out, err), 0) << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  EXPECT_EQ(doc["partNumber"], "8700340");
  EXPECT_EQ(doc["markerCount"], 4);
  EXPECT_EQ(doc["date"], "2005-01-10");
  EXPECT_TRUE(doc["checksumOk"].get<bool>());
  EXPECT_NEAR(doc["geometry"]["segments"][0]["mm"].get<double>(), 50.0, 1e-3);  // markers 1-2
  EXPECT_LT(doc["geometry"]["offPlaneRmsMm"].get<double>(), 1e-3);                // all in x = 0
  std::ostringstream out2, err2;
  ASSERT_EQ(RunToolInfoCommand({kRoms + "8700248.rom", "--json"}, out2, err2), 0) << err2.str();
  EXPECT_TRUE(nlohmann::json::parse(out2.str())["geometry"]["collinear"].get<bool>());
  std::ostringstream out3, err3;
  EXPECT_EQ(RunToolInfoCommand({std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/none.rom"}, out3, err3), 1);
  EXPECT_NE(err3.str().find("cannot open"), std::string::npos) << err3.str();
}
