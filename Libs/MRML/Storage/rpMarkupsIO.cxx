#include "rpMarkupsIO.h"

#include <vector>

#include "rpAtomicFile.h"
#include "rpMarkupsFormat.h"
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"
#include "vtkRPFiducialListNode.h"

namespace rp {
namespace {

using ControlPoints = std::vector<ControlPoint>;

// Replaces the node's points in one batch (one ModifiedEvent), after the whole file was parsed.
void ReplacePoints(vtkRPFiducialListNode* node, const ControlPoints& points) {
  const int previous = node->StartModify();
  node->RemoveAllControlPoints();
  for (const auto& p : points) node->AddControlPoint(p);
  node->EndModify(previous);
}

bool ReadWith(bool (*parse)(const std::string&, const std::string&, ControlPoints&, std::string&),
              const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  if (!node) {
    error = "no fiducial list to read '" + path + "' into";
    return false;
  }
  std::string text;
  if (!ReadFile(path, text, error)) return false;
  ControlPoints points;
  if (!parse(text, path, points, error)) return false;
  ReplacePoints(node, points);
  return true;
}

}  // namespace

bool WriteMarkupsJson(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  if (!node) {
    error = "no fiducial list to write to '" + path + "'";
    return false;
  }
  return WriteFileAtomically(path, FormatMarkupsJson(node->GetControlPoints(), node->GetColor()), error);
}

bool ReadMarkupsJson(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  return ReadWith(&ParseMarkupsJson, path, node, error);
}

bool WriteFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  if (!node) {
    error = "no fiducial list to write to '" + path + "'";
    return false;
  }
  return WriteFileAtomically(path, FormatFcsv(node->GetControlPoints()), error);
}

bool ReadFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error) {
  return ReadWith(&ParseFcsv, path, node, error);
}

namespace {
class FiducialListStorage : public NodeStorage {
 public:
  std::string Description() const override { return "fiducial list (Slicer .mrk.json/.fcsv)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPFiducialListNode");
  }
  std::vector<std::string> Extensions() const override { return {".mrk.json", ".fcsv"}; }
  std::string DefaultExtension() const override { return ".mrk.json"; }
  std::string NodeClassForFiles() const override { return "vtkRPFiducialListNode"; }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    return HasExtension(path, ".fcsv") ? WriteFcsv(path, list, error) : WriteMarkupsJson(path, list, error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    auto* list = vtkRPFiducialListNode::SafeDownCast(node);
    return HasExtension(path, ".fcsv") ? ReadFcsv(path, list, error) : ReadMarkupsJson(path, list, error);
  }
};
}  // namespace

std::shared_ptr<NodeStorage> MakeFiducialListStorage() { return std::make_shared<FiducialListStorage>(); }

}  // namespace rp
