// Fiducial files in the layouts 3D Slicer writes (.mrk.json schema v1.0.3, .fcsv 4.11 and older),
// written here by hand from Slicer's documentation and storage node source, with the LPS ↔ RAS
// conversion checked on hand-negated coordinates.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpMarkupsFormat.h"
#include "rpMarkupsIO.h"
#include "rpNodeStorage.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPScene.h"

namespace {

std::string OutputDir() {
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/markups";
  std::filesystem::create_directories(dir);
  return dir;
}

std::string WriteText(const std::string& name, const std::string& text) {
  const std::string path = OutputDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void ExpectPosition(const vtkRPFiducialListNode* node, int n, double r, double a, double s) {
  double p[3];
  node->GetNthControlPointPosition(n, p);
  EXPECT_DOUBLE_EQ(p[0], r) << "point " << n;
  EXPECT_DOUBLE_EQ(p[1], a) << "point " << n;
  EXPECT_DOUBLE_EQ(p[2], s) << "point " << n;
}

// As Slicer 5 writes a point list (LPS), with one point not yet placed ("position": "").
const char* const SlicerJson = R"({
    "@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",
    "markups": [
        {
            "type": "Fiducial",
            "coordinateSystem": "LPS",
            "coordinateUnits": "mm",
            "locked": false,
            "fixedNumberOfControlPoints": false,
            "labelFormat": "%N-%d",
            "lastUsedControlPointNumber": 3,
            "controlPoints": [
                {
                    "id": "1",
                    "label": "F-1",
                    "description": "nasion",
                    "associatedNodeID": "vtkMRMLScalarVolumeNode1",
                    "position": [-53.388409961685827, -73.33572796934868, 12.5],
                    "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],
                    "selected": true,
                    "locked": false,
                    "visibility": true,
                    "positionStatus": "defined"
                },
                {
                    "id": "2",
                    "label": "F-2",
                    "description": "",
                    "associatedNodeID": "",
                    "position": [49.8682950191571, -88.58955938697324, 0.0],
                    "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],
                    "selected": false,
                    "locked": true,
                    "visibility": false,
                    "positionStatus": "defined"
                },
                {
                    "id": "3",
                    "label": "F-3",
                    "description": "",
                    "associatedNodeID": "",
                    "position": "",
                    "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],
                    "selected": true,
                    "locked": false,
                    "visibility": true,
                    "positionStatus": "undefined"
                }
            ],
            "measurements": [],
            "display": { "visibility": true, "opacity": 1.0, "color": [0.4, 1.0, 1.0] }
        }
    ]
})";

TEST(MarkupsIO, ReadsSlicerJsonInLPS) {
  const std::string path = WriteText("slicer.mrk.json", SlicerJson);
  vtkNew<vtkRPFiducialListNode> node;
  std::string error;
  ASSERT_TRUE(rp::ReadMarkupsJson(path, node, error)) << error;
  ASSERT_EQ(node->GetNumberOfControlPoints(), 2);  // the undefined point has no position
  ExpectPosition(node, 0, 53.388409961685827, 73.33572796934868, 12.5);
  ExpectPosition(node, 1, -49.8682950191571, 88.58955938697324, 0.0);
  const auto& p0 = node->GetNthControlPoint(0);
  const auto& p1 = node->GetNthControlPoint(1);
  EXPECT_EQ(p0.ID, "1");
  EXPECT_EQ(p0.Label, "F-1");
  EXPECT_EQ(p0.Description, "nasion");
  EXPECT_TRUE(p0.Selected);
  EXPECT_FALSE(p0.Locked);
  EXPECT_TRUE(p0.Visible);
  EXPECT_EQ(p1.Label, "F-2");
  EXPECT_FALSE(p1.Selected);
  EXPECT_TRUE(p1.Locked);
  EXPECT_FALSE(p1.Visible);
}

TEST(MarkupsIO, ReadsDocumentedMinimalJsonAndRAS) {
  // The minimal example of Slicer's developer guide (schema v1.0.0, LPS, label + position only).
  const std::string minimal = WriteText("minimal.mrk.json", R"({"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.0.json#",
"markups": [{"type": "Fiducial", "coordinateSystem": "LPS", "controlPoints": [
    { "label": "F-1", "position": [-53.388409961685827, -73.33572796934868, 0.0] },
    { "label": "F-2", "position": [49.8682950191571, -88.58955938697324, 0.0] },
    { "label": "F-3", "position": [-25.22749042145594, 59.255268199233729, 0.0] }
]}]})");
  vtkNew<vtkRPFiducialListNode> node;
  std::string error;
  ASSERT_TRUE(rp::ReadMarkupsJson(minimal, node, error)) << error;
  ASSERT_EQ(node->GetNumberOfControlPoints(), 3);
  ExpectPosition(node, 2, 25.22749042145594, -59.255268199233729, 0.0);
  EXPECT_FALSE(node->GetNthControlPoint(2).ID.empty());  // generated when the file has none

  const std::string ras = WriteText("ras.mrk.json", R"({"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",
"markups": [{"type": "Fiducial", "coordinateSystem": "RAS", "controlPoints": [
    { "id": "7", "label": "A", "position": [1.5, -2.5, 3.5], "positionStatus": "defined" } ]}]})");
  ASSERT_TRUE(rp::ReadMarkupsJson(ras, node, error)) << error;
  ASSERT_EQ(node->GetNumberOfControlPoints(), 1);  // replaced, not appended
  ExpectPosition(node, 0, 1.5, -2.5, 3.5);
}

TEST(MarkupsIO, WritesJsonAsSlicerDoes) {
  vtkNew<vtkRPFiducialListNode> node;
  node->SetName("F");
  const double a[3] = {10.25, -20.5, 30.75}, b[3] = {-1, 2, -3}, c[3] = {0.1, 0.2, 0.3};
  node->AddControlPoint(a, "nasion");
  node->AddControlPoint(b, "tragus, left");
  node->AddControlPoint(c);
  node->SetNthControlPointLocked(1, true);
  node->SetNthControlPointSelected(2, false);
  const std::string path = OutputDir() + "/written.mrk.json";
  std::string error;
  ASSERT_TRUE(rp::WriteMarkupsJson(path, node, error)) << error;

  const auto doc = nlohmann::json::parse(ReadText(path));
  EXPECT_EQ(doc["@schema"],
            "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/"
            "markups-schema-v1.0.3.json#");
  const auto& m = doc["markups"][0];
  EXPECT_EQ(m["type"], "Fiducial");
  EXPECT_EQ(m["coordinateSystem"], "LPS");
  ASSERT_EQ(m["controlPoints"].size(), 3u);
  const auto& p0 = m["controlPoints"][0];
  for (const char* key : {"id", "label", "description", "associatedNodeID", "position", "orientation", "selected",
                          "locked", "visibility", "positionStatus"}) {
    EXPECT_TRUE(p0.contains(key)) << key;
  }
  EXPECT_EQ(p0["positionStatus"], "defined");
  EXPECT_DOUBLE_EQ(p0["position"][0].get<double>(), -10.25);  // LPS: x and y negated
  EXPECT_DOUBLE_EQ(p0["position"][1].get<double>(), 20.5);
  EXPECT_DOUBLE_EQ(p0["position"][2].get<double>(), 30.75);
  EXPECT_EQ(p0["orientation"].size(), 9u);
  EXPECT_EQ(m["controlPoints"][1]["locked"], true);
  EXPECT_EQ(m["controlPoints"][2]["selected"], false);

  vtkNew<vtkRPFiducialListNode> back;
  ASSERT_TRUE(rp::ReadMarkupsJson(path, back, error)) << error;
  ASSERT_EQ(back->GetNumberOfControlPoints(), 3);
  for (int n = 0; n < 3; ++n) {
    const auto& x = node->GetNthControlPoint(n);
    const auto& y = back->GetNthControlPoint(n);
    EXPECT_EQ(x.ID, y.ID);
    EXPECT_EQ(x.Label, y.Label);
    EXPECT_EQ(x.Selected, y.Selected);
    EXPECT_EQ(x.Locked, y.Locked);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x.Position[k], y.Position[k]);  // exact round trip
  }
}

TEST(MarkupsIO, ReadsFcsvVersionsAndCoordinateSystems) {
  // Slicer 4.11+ (LPS), with a quoted label holding a comma and a quote.
  const std::string v411 = WriteText("v411.fcsv",
                                     "# Markups fiducial file version = 4.11\n"
                                     "# CoordinateSystem = LPS\n"
                                     "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                                     "1,-10.5,20,30,0,0,0,1,1,1,0,F-1,,\n"
                                     "2,1,-2,3,0,0,0,1,0,0,1,\"tragus, \"\"left\"\"\",note,vtkMRMLScalarVolumeNode1\n");
  vtkNew<vtkRPFiducialListNode> node;
  std::string error;
  ASSERT_TRUE(rp::ReadFcsv(v411, node, error)) << error;
  ASSERT_EQ(node->GetNumberOfControlPoints(), 2);
  ExpectPosition(node, 0, 10.5, -20, 30);
  ExpectPosition(node, 1, -1, 2, 3);
  EXPECT_EQ(node->GetNthControlPoint(1).Label, "tragus, \"left\"");
  EXPECT_EQ(node->GetNthControlPoint(1).Description, "note");
  EXPECT_FALSE(node->GetNthControlPoint(1).Visible);
  EXPECT_FALSE(node->GetNthControlPoint(1).Selected);
  EXPECT_TRUE(node->GetNthControlPoint(1).Locked);

  // Slicer 4.6 - 4.10: RAS, written as "0" ("1" meant LPS), ids named after the node.
  const std::string v46 = WriteText("v46.fcsv",
                                    "# Markups fiducial file version = 4.6\n"
                                    "# CoordinateSystem = 0\n"
                                    "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                                    "vtkMRMLMarkupsFiducialNode_0,-10.5,20,30,0,0,0,1,1,1,0,F-1,,\r\n");
  ASSERT_TRUE(rp::ReadFcsv(v46, node, error)) << error;
  ASSERT_EQ(node->GetNumberOfControlPoints(), 1);
  ExpectPosition(node, 0, -10.5, 20, 30);
  EXPECT_EQ(node->GetNthControlPoint(0).ID, "vtkMRMLMarkupsFiducialNode_0");

  const std::string lps1 = WriteText("lps1.fcsv",
                                     "# Markups fiducial file version = 4.10\n"
                                     "# CoordinateSystem = 1\n"
                                     "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                                     "a,-10.5,20,30,0,0,0,1,1,1,0,F-1,,\n");
  ASSERT_TRUE(rp::ReadFcsv(lps1, node, error)) << error;
  ExpectPosition(node, 0, 10.5, -20, 30);

  const std::string ras = WriteText("ras.fcsv",
                                    "# Markups fiducial file version = 4.11\n"
                                    "# CoordinateSystem = RAS\n"
                                    "1,-10.5,20,30,0,0,0,1,1,1,0,F-1,,\n");
  ASSERT_TRUE(rp::ReadFcsv(ras, node, error)) << error;
  ExpectPosition(node, 0, -10.5, 20, 30);
}

TEST(MarkupsIO, WritesFcsvAsSlicerDoes) {
  vtkNew<vtkRPFiducialListNode> node;
  const double a[3] = {10.25, -20.5, 30.75}, b[3] = {1.0 / 3.0, 2, -3};
  node->AddControlPoint(a, "nasion");
  node->AddControlPoint(b, "tragus, left");
  const std::string path = OutputDir() + "/written.fcsv";
  std::string error;
  ASSERT_TRUE(rp::WriteFcsv(path, node, error)) << error;
  std::istringstream lines(ReadText(path));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "# Markups fiducial file version = 4.11");
  std::getline(lines, line);
  EXPECT_EQ(line, "# CoordinateSystem = LPS");
  std::getline(lines, line);
  EXPECT_EQ(line, "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID");
  std::getline(lines, line);
  EXPECT_EQ(line, node->GetNthControlPoint(0).ID + ",-10.25,20.5,30.75,0,0,0,1,1,1,0,nasion,,");
  std::getline(lines, line);
  EXPECT_NE(line.find(",\"tragus, left\","), std::string::npos) << line;

  vtkNew<vtkRPFiducialListNode> back;
  ASSERT_TRUE(rp::ReadFcsv(path, back, error)) << error;
  ASSERT_EQ(back->GetNumberOfControlPoints(), 2);
  EXPECT_EQ(back->GetNthControlPoint(1).Label, "tragus, left");
  for (int k = 0; k < 3; ++k) EXPECT_EQ(back->GetNthControlPoint(1).Position[k], b[k]);
}

TEST(MarkupsIO, BadFilesLeaveTheListUntouched) {
  vtkNew<vtkRPFiducialListNode> node;
  const double a[3] = {1, 2, 3};
  node->AddControlPoint(a, "kept");
  std::string error;
  const std::string schemaLine =
      "{\"@schema\": \"https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/"
      "Schema/markups-schema-v1.0.3.json#\",";
  const std::vector<std::pair<std::string, std::string>> badJson = {
      {"truncated.mrk.json", schemaLine + "\"markups\": [{\"type\": \"Fiducial\", "},
      {"noschema.mrk.json", "{\"markups\": []}"},
      {"line.mrk.json", schemaLine + "\"markups\": [{\"type\": \"Line\", \"controlPoints\": []}]}"},
      {"ijk.mrk.json", schemaLine + "\"markups\": [{\"type\": \"Fiducial\", \"coordinateSystem\": \"IJK\"}]}"},
      {"shortpos.mrk.json",
       schemaLine + "\"markups\": [{\"type\": \"Fiducial\", \"controlPoints\": [{\"position\": [1, 2]}]}]}"},
  };
  for (const auto& [name, text] : badJson) {
    error.clear();
    EXPECT_FALSE(rp::ReadMarkupsJson(WriteText(name, text), node, error)) << name;
    EXPECT_NE(error.find(name), std::string::npos) << error;
  }
  const std::vector<std::pair<std::string, std::string>> badFcsv = {
      {"noheader.fcsv", "1,2,3,4\n"},
      {"badnumber.fcsv", "# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n1,abc,2,3,0,0,0,1,1,1,0,F,,\n"},
      {"ijk.fcsv", "# Markups fiducial file version = 4.11\n# CoordinateSystem = 2\n1,1,2,3,0,0,0,1,1,1,0,F,,\n"},
      {"short.fcsv", "# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n1,1,2\n"},
  };
  for (const auto& [name, text] : badFcsv) {
    error.clear();
    EXPECT_FALSE(rp::ReadFcsv(WriteText(name, text), node, error)) << name;
    EXPECT_NE(error.find(name), std::string::npos) << error;
  }
  EXPECT_FALSE(rp::ReadFcsv(OutputDir() + "/missing.fcsv", node, error));
  ASSERT_EQ(node->GetNumberOfControlPoints(), 1);
  EXPECT_EQ(node->GetNthControlPoint(0).Label, "kept");
  ExpectPosition(node, 0, 1, 2, 3);
}

TEST(MarkupsIO, RegisteredAsNodeStorage) {
  vtkNew<vtkRPFiducialListNode> node;
  const rp::NodeStorage* storage = rp::FindNodeStorage(node);
  ASSERT_NE(storage, nullptr);
  EXPECT_EQ(storage->DefaultExtension(), ".mrk.json");
  EXPECT_EQ(storage->NodeClassForFiles(), "vtkRPFiducialListNode");
  EXPECT_EQ(rp::FindNodeStorageForFile("a/b/Points.MRK.JSON"), storage);
  EXPECT_EQ(rp::FindNodeStorageForFile("Points.fcsv"), storage);

  vtkNew<vtkRPScene> scene;
  std::string error;
  vtkRPNode* loaded = rp::LoadDataFile(scene, WriteText("storage.mrk.json", SlicerJson), error);
  ASSERT_NE(loaded, nullptr) << error;
  auto* list = vtkRPFiducialListNode::SafeDownCast(loaded);
  ASSERT_NE(list, nullptr);
  EXPECT_EQ(list->GetNumberOfControlPoints(), 2);

  const std::string fcsv = OutputDir() + "/storage.fcsv";
  ASSERT_TRUE(rp::SaveDataFile(list, fcsv, error)) << error;
  EXPECT_EQ(ReadText(fcsv).rfind("# Markups fiducial file version = 4.11", 0), 0u);
}

}  // namespace

// Labels as other tools write them round-trip: a label starting with '#' (a comment line in a
// .fcsv unless quoted), commas, quotes and line breaks; a Latin-1 label read from a .fcsv
// writes as .mrk.json (replaced, not thrown). Both failed before (found while writing the
// markups fuzzer's write-back check).
TEST(MarkupsIO, AwkwardLabelsRoundTrip) {
  std::vector<rp::ControlPoint> points(3);
  points[0].ID = "#1";
  points[0].Label = "#hash, \"quoted\"";
  points[1].Label = "two\r\nlines";
  points[2].Label = std::string("caf\xE9");  // Latin-1, not UTF-8
  for (int i = 0; i < 3; ++i) points[static_cast<size_t>(i)].Position[0] = i;
  std::vector<rp::ControlPoint> back;
  std::string error;
  ASSERT_TRUE(rp::ParseFcsv(rp::FormatFcsv(points), "t.fcsv", back, error)) << error;
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].ID, "#1");
  EXPECT_EQ(back[0].Label, "#hash, \"quoted\"");
  EXPECT_EQ(back[1].Label, "two  lines");
  const double color[3] = {1, 1, 1};
  std::string json;
  ASSERT_NO_THROW(json = rp::FormatMarkupsJson(points, color));
  back.clear();
  ASSERT_TRUE(rp::ParseMarkupsJson(json, "t.mrk.json", back, error)) << error;
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].Label, "#hash, \"quoted\"");
  EXPECT_EQ(back[2].Label.substr(0, 3), "caf");
}
