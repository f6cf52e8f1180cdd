#include "rpMarkupsIO.h"

#include <set>
#include <vector>

#include "rpAtomicFile.h"
#include "rpMarkupsFormat.h"
#include "rpMrmlNames.h"
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPMarkupsNode.h"
#include "vtkRPTrajectoryNode.h"

namespace rp {
namespace {

using ControlPoints = std::vector<ControlPoint>;

// The class each markups type loads into by default (a subclass travels in RoboPlan.Class).
const char* DefaultClassForType(const std::string& type) {
  if (type == "Line") return "vtkRPTrajectoryNode";
  if (type == "Plane") return "vtkRPCutPlaneNode";
  return "vtkRPFiducialListNode";
}

// Replaces the node's points in one batch (one ModifiedEvent), after the whole file was parsed.
void ReplacePoints(vtkRPMarkupsNode* node, const ControlPoints& points) {
  const int previous = node->StartModify();
  node->RemoveAllControlPoints();
  for (const auto& p : points) node->AddControlPoint(p);
  node->EndModify(previous);
}

MarkupsDocument DocumentOf(vtkRPMarkupsNode* node) {
  MarkupsDocument document;
  document.Type = node->GetMarkupsType();
  document.Name = node->GetName();
  document.Points = node->GetControlPoints();
  node->GetColor(document.Color);
  document.Attributes = node->GetAttributes();
  vtkRPNode::PropertyMap properties;
  node->WriteProperties(properties);
  for (const auto& [key, value] : properties)
    if (!IsMarkupsFileField(key)) document.Attributes[MrmlOwnPrefix + key] = value;
  if (node->GetClassName() != std::string(DefaultClassForType(document.Type)))
    document.Attributes[MrmlOwnClassAttribute] = node->GetClassName();
  if (auto* plane = vtkRPCutPlaneNode::SafeDownCast(node)) {
    plane->GetOrigin(document.Origin);
    plane->GetNormal(document.Normal);
    plane->GetXAxis(document.XAxis);
    document.Size[0] = plane->GetSize()[0];
    document.Size[1] = plane->GetSize()[1];
  }
  return document;
}

// A plane keeps one control point, its origin (a 3-point plane from Slicer becomes point-normal).
void ApplyPlane(const MarkupsDocument& document, vtkRPCutPlaneNode* plane) {
  ControlPoints points;
  if (!document.Points.empty()) points.push_back(document.Points.front());
  else points.emplace_back();
  for (int i = 0; i < 3; ++i) points[0].Position[i] = document.Origin[i];
  if (points[0].Label.empty()) points[0].Label = "origin";
  ReplacePoints(plane, points);
  plane->SetNormal(document.Normal);
  plane->SetXAxis(document.XAxis);
  if (document.Size[0] > 0 && document.Size[1] > 0) plane->SetSize(document.Size[0], document.Size[1]);
}

void Apply(const MarkupsDocument& document, vtkRPMarkupsNode* node) {
  const int previous = node->StartModify();
  vtkRPNode::PropertyMap properties;
  for (const auto& [key, value] : document.Attributes) {
    if (key == MrmlOwnClassAttribute) continue;
    if (key.rfind(MrmlOwnPrefix, 0) == 0) properties[key.substr(std::string(MrmlOwnPrefix).size())] = value;
    else node->SetAttribute(key, value);
  }
  if (!properties.empty()) node->ReadProperties(properties);
  if (auto* plane = vtkRPCutPlaneNode::SafeDownCast(node)) ApplyPlane(document, plane);
  else ReplacePoints(node, document.Points);
  if (document.HasColor) node->SetColor(document.Color[0], document.Color[1], document.Color[2]);
  node->EndModify(previous);
}

}  // namespace

bool IsMarkupsFileField(const std::string& key) {
  static const std::set<std::string> keys = {"color", "normal", "xAxis", "sizeMm"};
  return keys.count(key) > 0;
}

std::string MarkupsNodeClassForFile(const std::string& path, std::string& error) {
  std::string text;
  if (!ReadFile(path, text, error)) return "";
  MarkupsDocument document;
  if (!ParseMarkupsDocument(text, path, document, error)) return "";
  const auto subclass = document.Attributes.find(MrmlOwnClassAttribute);
  return subclass != document.Attributes.end() ? subclass->second : DefaultClassForType(document.Type);
}

bool WriteMarkupsJson(const std::string& path, vtkRPMarkupsNode* node, std::string& error) {
  if (!node) {
    error = "no markups node to write to '" + path + "'";
    return false;
  }
  return WriteFileAtomically(path, FormatMarkupsDocument(DocumentOf(node)), error);
}

bool ReadMarkupsJson(const std::string& path, vtkRPMarkupsNode* node, std::string& error) {
  if (!node) {
    error = "no markups node to read '" + path + "' into";
    return false;
  }
  std::string text;
  if (!ReadFile(path, text, error)) return false;
  MarkupsDocument document;
  if (!ParseMarkupsDocument(text, path, document, error, {node->GetMarkupsType()})) return false;
  Apply(document, node);
  return true;
}

bool WriteFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  if (!node) {
    error = "no fiducial list to write to '" + path + "'";
    return false;
  }
  return WriteFileAtomically(path, FormatFcsv(node->GetControlPoints()), error);
}

bool ReadFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  if (!node) {
    error = "no fiducial list to read '" + path + "' into";
    return false;
  }
  std::string text;
  if (!ReadFile(path, text, error)) return false;
  ControlPoints points;
  if (!ParseFcsv(text, path, points, error)) return false;
  ReplacePoints(node, points);
  return true;
}

namespace {
// Every markups node: .mrk.json; fiducial lists also .fcsv.
class MarkupsStorage : public NodeStorage {
 public:
  std::string Description() const override { return "markups (Slicer .mrk.json/.fcsv)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPMarkupsNode");
  }
  std::vector<std::string> Extensions() const override { return {".mrk.json", ".fcsv"}; }
  std::string DefaultExtension() const override { return ".mrk.json"; }
  std::string NodeClassForFiles() const override { return "vtkRPFiducialListNode"; }
  std::string NodeClassForFile(const std::string& path, std::string& error) const override {
    return HasExtension(path, ".fcsv") ? this->NodeClassForFiles() : MarkupsNodeClassForFile(path, error);
  }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    if (!HasExtension(path, ".fcsv")) return WriteMarkupsJson(path, vtkRPMarkupsNode::SafeDownCast(node), error);
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    if (!list) error = "'" + path + "': only point lists go in a .fcsv; save a " + node->GetNodeTagName() + " as .mrk.json";
    return list && WriteFcsv(path, list, error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    if (!HasExtension(path, ".fcsv")) return ReadMarkupsJson(path, vtkRPMarkupsNode::SafeDownCast(node), error);
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    if (!list) error = "'" + path + "': a .fcsv holds a point list, not a " + node->GetNodeTagName();
    return list && ReadFcsv(path, list, error);
  }
};
}  // namespace

std::shared_ptr<NodeStorage> MakeMarkupsStorage() { return std::make_shared<MarkupsStorage>(); }

}  // namespace rp
