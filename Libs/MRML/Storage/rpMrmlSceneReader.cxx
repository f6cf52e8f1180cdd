// Reading 3D Slicer's .mrml scenes and .mrb bundles into a vtkRPScene (rpMrmlScene.h).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <set>
#include <sstream>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>

#include "rpMemoryBudget.h"
#include "rpModelIO.h"
#include "rpMrmlBundle.h"
#include "rpMrmlNames.h"
#include "rpMrmlScene.h"
#include "rpMrmlText.h"
#include "rpNodeStorage.h"
#include "rpXmlDocument.h"
#include "vtkRPMarkupsNode.h"
#include "vtkRPLayoutNode.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// One node element of the scene file, with its links in one form whatever form the file used.
struct MrmlElement {
  std::string Tag;
  std::map<std::string, std::string> Atts;
  MrmlReferences Refs;
  std::string Att(const std::string& key) const {
    const auto it = this->Atts.find(key);
    return it == this->Atts.end() ? std::string() : it->second;
  }
  bool Has(const std::string& key) const { return this->Atts.count(key) > 0; }
  std::string Ref(const std::string& role) const {
    for (const auto& [name, ids] : this->Refs)
      if (name == role && !ids.empty()) return ids.front();
    return "";
  }
};

struct ReadContext {
  fs::path Folder;        // the scene file's folder (file names are relative to it)
  bool Confined = false;  // a bundle: data files must be inside Folder
  vtkRPScene* Scene = nullptr;
  SceneTransferReport* Report = nullptr;
  std::map<std::string, const MrmlElement*> ByID;
  std::vector<vtkSmartPointer<vtkRPNode>> Loaded;
  std::map<std::string, int> Unsupported;  // tag -> count
  std::set<std::string> Failed;             // MRML IDs of nodes that could not be loaded
  const MrmlElement* Linked(const MrmlElement& element, const std::string& role) const {
    const auto it = this->ByID.find(element.Ref(role));
    return it == this->ByID.end() ? nullptr : it->second;
  }
};

// Slicer's reference roles and the attribute names older scenes used for them.
const std::pair<const char*, const char*> LegacyLinks[] = {
    {"displayNodeRef", "display"},           {"storageNodeRef", "storage"},
    {"transformNodeRef", "transform"},       {"backgroundVolumeID", "backgroundVolume"},
    {"foregroundVolumeID", "foregroundVolume"}, {"labelVolumeID", "labelVolume"}};

MrmlElement ToElement(vtkXMLDataElement* xml) {
  MrmlElement element;
  element.Tag = xml->GetName() ? xml->GetName() : "";
  for (int n = 0; n < xml->GetNumberOfAttributes(); ++n)
    element.Atts[xml->GetAttributeName(n)] = xml->GetAttributeValue(n) ? xml->GetAttributeValue(n) : "";
  // As vtkMRMLNode::ReadXMLAttributes: `references` first, the legacy names for roles not seen.
  element.Refs = ParseMrmlReferences(element.Att("references"));
  for (const auto& [attribute, role] : LegacyLinks) {
    if (!element.Has(attribute) || !element.Ref(role).empty()) continue;
    std::stringstream ids(element.Att(attribute));
    std::vector<std::string> values;
    for (std::string id; ids >> id;) values.push_back(id);
    if (!values.empty()) element.Refs.emplace_back(role, values);
  }
  return element;
}

void Skip(ReadContext& context, const std::string& what, const std::string& why) {
  context.Report->Skipped.push_back({what, why});
}

// The data file a storage element names: URL-decoded once, or twice (some bundles), relative to
// the scene. "" with `why` set when it cannot be found.
std::string ResolveDataFile(const ReadContext& context, const std::string& fileName, std::string& why) {
  const std::string once = MrmlUrlDecode(fileName), twice = MrmlUrlDecode(once);
  for (const std::string& name : {once, twice}) {
    const fs::path path = fs::path(name).is_absolute() ? fs::path(name) : context.Folder / name;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;
    if (context.Confined) {
      const fs::path real = fs::weakly_canonical(path, ec), root = fs::weakly_canonical(context.Folder, ec);
      const std::string r = real.string(), base = root.string() + "/";
      if (r.compare(0, base.size(), base) != 0) {
        why = "it lies outside the bundle";
        return "";
      }
    }
    return path.string();
  }
  why = "file is missing";
  return "";
}

// Reads the node's data file through its storage element. False (and a skip entry) on failure.
bool ReadData(ReadContext& context, const MrmlElement& element, vtkRPNode* node,
              const std::function<bool(const std::string&, std::string&)>& read) {
  const MrmlElement* storage = context.Linked(element, "storage");
  const std::string fileName = storage ? storage->Att("fileName") : "";
  const std::string what = (fileName.empty() ? element.Tag : MrmlUrlDecode(fileName)) + " (node '" + node->GetName() + "')";
  if (fileName.empty()) {
    Skip(context, what, "the node has no data file");
    return false;
  }
  std::string why;
  const std::string path = ResolveDataFile(context, fileName, why);
  if (!path.empty()) {
    if (read(path, why)) {
      context.Report->Files.push_back(fs::relative(path, context.Folder).generic_string());
      return true;
    }
    if (why.empty()) why = "could not be read";
  }
  Skip(context, what, why);
  return false;
}

// Reads through the registry's storage for the file's extension (the same readers as
// `roboplan <file>`), refusing a file of another kind of data.
bool ReadThroughRegistry(vtkRPNode* node, const std::string& path, std::string& why) {
  const NodeStorage* storage = FindNodeStorageForFile(path);
  if (!storage || !storage->CanHandle(node)) {
    why = "no reader for this file type for a " + std::string(node->GetNodeTagName()) + " node";
    return false;
  }
  return storage->Read(node, path, why);
}

// A node of our class for an element: ID, name, attributes, our own fields (RoboPlan.* MRML
// attributes, rpMrmlNames.h) and the parent transform.
vtkSmartPointer<vtkRPNode> NewNode(ReadContext& context, const MrmlElement& element, const char* className) {
  std::map<std::string, std::string> attributes = ParseMrmlAttributes(element.Att("attributes"));
  vtkRPNode::PropertyMap properties;
  std::string ourClass = className;
  for (auto it = attributes.begin(); it != attributes.end();) {
    const std::string key = it->first;
    if (key.rfind(MrmlOwnPrefix, 0) != 0) {
      ++it;
      continue;
    }
    if (key == MrmlOwnClassAttribute) ourClass = it->second;
    else properties[key.substr(std::string(MrmlOwnPrefix).size())] = it->second;
    it = attributes.erase(it);
  }
  vtkSmartPointer<vtkRPNode> node = context.Scene->CreateNodeByClass(ourClass);
  if (!node || !node->IsA(className)) node = context.Scene->CreateNodeByClass(className);
  node->SetIDInternal(element.Att("id"));
  node->SetName(element.Att("name"));
  try {
    node->ReadProperties(properties);
  } catch (const std::exception& e) {
    context.Report->Warnings.push_back("node '" + node->GetName() + "': RoboPlan fields ignored (" + e.what() + ")");
  }
  for (const auto& [key, value] : attributes) node->SetAttribute(key, value);
  if (!element.Ref("transform").empty() && node->IsA("vtkRPTransformableNode"))
    node->AddNodeReferenceID(vtkRPTransformableNode::TransformRole(), element.Ref("transform"));
  return node;
}

bool ReadColor(const MrmlElement* element, const char* key, double color[3]) {
  std::vector<double> values;
  if (!element || !ParseNumbers(element->Att(key), values, 3)) return false;
  for (int n = 0; n < 3; ++n) color[n] = values[n];
  return true;
}

vtkSmartPointer<vtkRPNode> ReadVolume(ReadContext& context, const MrmlElement& element) {
  auto node = NewNode(context, element, "vtkRPScalarVolumeNode");
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(node);
  if (!ReadData(context, element, node, [&](const std::string& path, std::string& why) { return ReadThroughRegistry(node, path, why); }))
    return nullptr;
  volume->SetWindowLevelFromScalarRange();
  if (element.Tag == "LabelMapVolume" || element.Att("labelMap") == "1") volume->SetAttribute(MrmlLabelMapAttribute, "true");
  const MrmlElement* display = context.Linked(element, "display");
  std::vector<double> window, level;
  if (display && ParseNumbers(display->Att("window"), window, 1) && ParseNumbers(display->Att("level"), level, 1))
    volume->SetWindowLevel(window[0], level[0]);
  return node;
}

vtkSmartPointer<vtkRPNode> ReadModel(ReadContext& context, const MrmlElement& element) {
  auto node = NewNode(context, element, "vtkRPModelNode");
  auto* model = vtkRPModelNode::SafeDownCast(node);
  const MrmlElement* storage = context.Linked(element, "storage");
  // Slicer: the storage node's coordinateSystem (RAS when absent: a scene older than 4.11),
  // overridden by a SPACE tag in the file.
  std::string space = storage && storage->Has("coordinateSystem") ? storage->Att("coordinateSystem") : "RAS";
  if (space == "0") space = "RAS";
  if (space == "1") space = "LPS";
  const bool read = ReadData(context, element, node, [&](const std::string& path, std::string& why) {
    auto mesh = vtkSmartPointer<vtkPolyData>::New();
    if (!FindNodeStorageForFile(path) || !FindNodeStorageForFile(path)->CanHandle(model))
      return ReadThroughRegistry(node, path, why);
    if (!ReadModelFile(path, mesh, why, space)) return false;
    model->SetPolyData(mesh);
    return true;
  });
  if (!read) return nullptr;
  const MrmlElement* display = context.Linked(element, "display");
  double color[3];
  if (ReadColor(display, "color", color)) model->SetColor(color);
  std::vector<double> opacity;
  if (display && ParseNumbers(display->Att("opacity"), opacity, 1)) model->SetOpacity(opacity[0]);
  if (display && display->Has("visibility")) model->SetVisibility(display->Att("visibility") != "false" && display->Att("visibility") != "0");
  // Slice intersections: `visibility2D` (Slicer >= 4.13), before it `sliceIntersectionVisibility`;
  // neither: off, Slicer's display-node default (vtkMRMLDisplayNode: Visibility2D = 0).
  if (display) {
    const std::string key = display->Has("visibility2D") ? "visibility2D" : "sliceIntersectionVisibility";
    model->SetSliceIntersectionVisibility(display->Att(key) == "true" || display->Att(key) == "1");
  }
  return node;
}

vtkSmartPointer<vtkRPNode> ReadTransform(ReadContext& context, const MrmlElement& element) {
  auto node = NewNode(context, element, "vtkRPLinearTransformNode");
  auto* transform = vtkRPLinearTransformNode::SafeDownCast(node);
  std::vector<double> matrix;
  const bool hasMatrix = ParseNumbers(element.Att("matrixTransformToParent"), matrix, 16);
  if (hasMatrix) transform->SetMatrixTransformToParent(matrix.data());
  // The storage file (full precision) wins over the attribute (6 digits in Slicer's files). A file
  // that cannot be read is reported (skipped); the node stays with the attribute's matrix, as
  // Slicer keeps it, unless there is no matrix either.
  if (context.Linked(element, "storage") &&
      !ReadData(context, element, node, [&](const std::string& path, std::string& why) { return ReadThroughRegistry(node, path, why); })) {
    if (!hasMatrix) return nullptr;
    transform->SetMatrixTransformToParent(matrix.data());
  }
  return node;
}

// "Segment_1 OverrideColorR:0.2 OverrideColorG:0.5 OverrideColorB:0.1 Visible:true ...|..."
void ApplySegmentDisplay(vtkRPSegmentationNode* segmentation, const std::string& text) {
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, '|')) {
    std::stringstream fields(item);
    std::string id, field;
    fields >> id;
    id = MrmlUrlDecode(id);
    const vtkRPSegmentationNode::Segment* found = segmentation->GetSegmentByID(id);
    if (!found) continue;
    vtkRPSegmentationNode::Segment segment = *found;
    double override[3] = {-1, -1, -1};
    while (fields >> field) {
      const size_t colon = field.find(':');
      const std::string key = field.substr(0, colon);
      const double value = colon == std::string::npos ? -1 : std::atof(field.c_str() + colon + 1);
      if (key == "OverrideColorR") override[0] = value;
      if (key == "OverrideColorG") override[1] = value;
      if (key == "OverrideColorB") override[2] = value;
    }
    if (override[0] >= 0 && override[1] >= 0 && override[2] >= 0) {
      for (int n = 0; n < 3; ++n) segment.Color[n] = override[n];
      segmentation->SetSegment(segment);
    }
  }
}

vtkSmartPointer<vtkRPNode> ReadSegmentation(ReadContext& context, const MrmlElement& element) {
  auto node = NewNode(context, element, "vtkRPSegmentationNode");
  if (!ReadData(context, element, node, [&](const std::string& path, std::string& why) { return ReadThroughRegistry(node, path, why); }))
    return nullptr;
  if (const MrmlElement* display = context.Linked(element, "display"))
    ApplySegmentDisplay(vtkRPSegmentationNode::SafeDownCast(node), display->Att("SegmentationDisplayProperties"));
  return node;
}

// Our fields of a node's MRML attributes (RoboPlan.<field>): applied again after its data file so
// that the scene's values win over a copy inside the file (a .mrk.json Slicer rewrote has none).
void ApplyOwnFields(ReadContext& context, const MrmlElement& element, vtkRPNode* node) {
  vtkRPNode::PropertyMap properties;
  for (const auto& [key, value] : ParseMrmlAttributes(element.Att("attributes")))
    if (key.rfind(MrmlOwnPrefix, 0) == 0 && key != MrmlOwnClassAttribute)
      properties[key.substr(std::string(MrmlOwnPrefix).size())] = value;
  try {
    node->ReadProperties(properties);
  } catch (const std::exception& e) {
    context.Report->Warnings.push_back("node '" + node->GetName() + "': RoboPlan fields ignored (" + e.what() + ")");
  }
}

// Point lists, lines and planes: the .mrk.json through the registry, then the scene's name, our
// fields and links (a screw's model), and Slicer's display colour.
vtkSmartPointer<vtkRPNode> ReadMarkups(ReadContext& context, const MrmlElement& element, const char* className) {
  auto node = NewNode(context, element, className);
  auto* markups = vtkRPMarkupsNode::SafeDownCast(node);
  if (context.Linked(element, "storage")) {
    const std::string name = markups->GetName();
    if (!ReadData(context, element, node, [&](const std::string& path, std::string& why) { return ReadThroughRegistry(node, path, why); }))
      return nullptr;
    markups->SetName(name);  // the scene's name, not the one inside the file
    ApplyOwnFields(context, element, node);
  }
  for (const char* role : MrmlPlanReferenceRoles())
    if (!element.Ref(role).empty()) node->SetNodeReferenceID(role, element.Ref(role));
  // Slicer draws control points in the display node's selectedColor (unselected: color).
  const MrmlElement* display = context.Linked(element, "display");
  double color[3];
  if (ReadColor(display, "selectedColor", color) || ReadColor(display, "color", color)) markups->SetColor(color);
  return node;
}

vtkSmartPointer<vtkRPNode> ReadFiducials(ReadContext& context, const MrmlElement& element) {
  return ReadMarkups(context, element, "vtkRPFiducialListNode");
}
vtkSmartPointer<vtkRPNode> ReadLine(ReadContext& context, const MrmlElement& element) {
  return ReadMarkups(context, element, "vtkRPTrajectoryNode");
}
vtkSmartPointer<vtkRPNode> ReadPlane(ReadContext& context, const MrmlElement& element) {
  return ReadMarkups(context, element, "vtkRPCutPlaneNode");
}

vtkSmartPointer<vtkRPNode> ReadSlice(ReadContext& context, const MrmlElement& element) {
  const std::string layoutName = !element.Att("layoutName").empty() ? element.Att("layoutName") : element.Att("singletonTag");
  if (layoutName.empty()) return nullptr;
  auto node = NewNode(context, element, "vtkRPSliceNode");
  auto* slice = vtkRPSliceNode::SafeDownCast(node);
  slice->SetLayoutName(layoutName);
  std::vector<double> values;
  vtkNew<vtkMatrix4x4> sliceToRAS;
  if (ParseNumbers(element.Att("sliceToRAS"), values, 16)) {
    sliceToRAS->DeepCopy(values.data());
    slice->SetSliceToRAS(sliceToRAS);
  }
  if (ParseNumbers(element.Att("fieldOfView"), values) && values.size() >= 2) slice->SetFieldOfView(values[0], values[1]);
  if (ParseNumbers(element.Att("xyzOrigin"), values) && values.size() >= 2) slice->SetXYOrigin(values[0], values[1]);
  if (element.Has("sliceVisibility")) slice->SetSliceVisible(element.Att("sliceVisibility") == "true");
  return node;
}

// Slicer keeps a view's layers in a SliceComposite node of the same layout name: onto our slice node.
void ApplySliceComposite(ReadContext& context, const MrmlElement& element) {
  const std::string layoutName = !element.Att("layoutName").empty() ? element.Att("layoutName") : element.Att("singletonTag");
  for (auto& node : context.Loaded) {
    auto* slice = vtkRPSliceNode::SafeDownCast(node);
    if (!slice || slice->GetLayoutName() != layoutName) continue;
    slice->SetBackgroundVolumeID(element.Ref("backgroundVolume"));
    slice->SetForegroundVolumeID(element.Ref("foregroundVolume"));
    std::vector<double> value;
    if (ParseNumbers(element.Att("foregroundOpacity"), value, 1)) slice->SetForegroundOpacity(value[0]);
    if (ParseNumbers(element.Att("labelOpacity"), value, 1)) slice->SetLabelOpacity(value[0]);
    return;
  }
}

vtkSmartPointer<vtkRPNode> ReadLayout(ReadContext& context, const MrmlElement& element) {
  auto node = NewNode(context, element, "vtkRPLayoutNode");
  std::vector<double> value;
  if (ParseNumbers(element.Att("currentViewArrangement"), value, 1))
    vtkRPLayoutNode::SafeDownCast(node)->SetViewArrangement(ArrangementFromSlicerLayout(static_cast<int>(value[0])));
  return node;
}

using ElementReader = vtkSmartPointer<vtkRPNode> (*)(ReadContext&, const MrmlElement&);
ElementReader ReaderFor(const std::string& tag) {
  static const std::map<std::string, ElementReader> readers = {
      {"Volume", ReadVolume},         {"LabelMapVolume", ReadVolume},   {"Model", ReadModel},
      {"LinearTransform", ReadTransform}, {"Segmentation", ReadSegmentation}, {"MarkupsFiducial", ReadFiducials},
      {"MarkupsLine", ReadLine},      {"MarkupsPlane", ReadPlane},
      {"Slice", ReadSlice},           {"Layout", ReadLayout}};
  const auto it = readers.find(tag);
  return it == readers.end() ? nullptr : it->second;
}

// A transform chain that loops: the link that closes the loop is dropped, and named.
void BreakTransformCycles(ReadContext& context) {
  std::map<std::string, vtkRPNode*> byID;
  for (auto& node : context.Loaded) byID[node->GetID()] = node;
  for (auto& node : context.Loaded) {
    std::vector<std::string> chain = {node->GetID()};
    for (vtkRPNode* at = node; at;) {
      const std::string parent = at->GetNodeReferenceID(vtkRPTransformableNode::TransformRole());
      if (parent.empty() || !byID.count(parent)) break;
      if (std::find(chain.begin(), chain.end(), parent) != chain.end()) {
        std::string path;
        for (const auto& id : chain) path += byID[id]->GetName() + " -> ";
        Skip(context, "the parent transform of '" + at->GetName() + "'",
             "a transform that is its own ancestor (" + path + byID[parent]->GetName() + "); the link is dropped");
        at->RemoveNodeReferenceIDs(vtkRPTransformableNode::TransformRole());
        break;
      }
      chain.push_back(parent);
      at = byID[parent];
    }
  }
}

// Links to nodes that were not loaded (unknown types, missing files), and parent links to nodes that
// are no transforms, are dropped, not left dangling.
void DropDanglingReferences(ReadContext& context) {
  std::map<std::string, vtkRPNode*> loaded;
  for (auto& node : context.Loaded) loaded[node->GetID()] = node;
  for (auto& node : context.Loaded) {
    for (const std::string& role : node->GetReferenceRoles()) {
      for (int n = node->GetNumberOfNodeReferences(role) - 1; n >= 0; --n) {
        const std::string id = node->GetNodeReferenceID(role, n);
        const bool parentIsNoTransform = role == vtkRPTransformableNode::TransformRole() && loaded.count(id) &&
                                         !loaded[id]->IsA("vtkRPLinearTransformNode");
        if (!loaded.count(id) || parentIsNoTransform) node->RemoveReferencesTo(id);
      }
    }
  }
}

void ReadElements(ReadContext& context, const std::vector<MrmlElement>& elements) {
  for (const MrmlElement& element : elements) {
    if (IsMrmlHelperTag(element.Tag)) continue;  // display/storage/composite: read with their node
    const ElementReader reader = ReaderFor(element.Tag);
    if (!reader) {
      ++context.Unsupported[element.Tag];
      continue;
    }
    vtkSmartPointer<vtkRPNode> node = reader(context, element);
    if (node) context.Loaded.push_back(node);
    else context.Failed.insert(element.Att("id"));
  }
  for (const MrmlElement& element : elements)
    if (element.Tag == "SliceComposite") ApplySliceComposite(context, element);
  if (!context.Unsupported.empty()) {
    std::string list;
    for (const auto& [tag, count] : context.Unsupported) list += (list.empty() ? "" : ", ") + tag + " x" + std::to_string(count);
    context.Report->Warnings.push_back("not loaded, RoboPlan has no such node types: " + list);
  }
}

bool ReadScene(const std::string& path, vtkRPScene* scene, SceneTransferReport& report, bool confined) {
  report = SceneTransferReport();
  std::string error;
  vtkSmartPointer<vtkXMLDataElement> root = ReadXmlFile(path, error);
  if (!root || std::string(root->GetName() ? root->GetName() : "") != "MRML") {
    report.Ok = false;
    report.Error = root ? "'" + path + "' is not a MRML scene (its root element is <" + root->GetName() + ">, not <MRML>)" : error;
    return false;
  }
  std::vector<MrmlElement> elements;
  for (int n = 0; n < root->GetNumberOfNestedElements(); ++n) elements.push_back(ToElement(root->GetNestedElement(n)));
  ReadContext context;
  context.Folder = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  context.Confined = confined;
  context.Scene = scene;
  context.Report = &report;
  for (const MrmlElement& element : elements)
    if (!element.Att("id").empty()) context.ByID[element.Att("id")] = &element;
  ReadElements(context, elements);
  DropDanglingReferences(context);
  BreakTransformCycles(context);
  scene->Import(context.Loaded);
  for (auto& node : context.Loaded) ++report.NodesByType[node->GetNodeTagName()];
  return true;
}

}  // namespace

std::string SceneTransferReport::FirstProblem() const {
  if (!this->Ok) return this->Error;
  return this->Skipped.empty() ? std::string() : this->Skipped.front().What + ": " + this->Skipped.front().Why;
}

bool ReadMrmlScene(const std::string& path, vtkRPScene* scene, SceneTransferReport& report, const MrmlReadOptions&) {
  return ReadScene(path, scene, report, false);
}

bool ReadMrmlBundle(const std::string& path, vtkRPScene* scene, SceneTransferReport& report,
                    const MrmlReadOptions& options) {
  report = SceneTransferReport();
  TemporaryFolder folder("roboplan-mrb");
  std::vector<std::string> entries;
  std::string error;
  uint64_t limit = options.MaxBundleBytes ? options.MaxBundleBytes : AvailableMemoryBytes();
  if (limit == 0) limit = uint64_t(4) << 30;
  if (folder.Path().empty()) error = "cannot make a temporary folder to unpack '" + path + "'";
  else if (UnpackBundle(path, folder.Path(), limit, entries, error) && FindMainScene(entries).empty())
    error = "'" + path + "' is no Slicer bundle: it holds no .mrml scene file";
  if (!error.empty()) {
    report.Ok = false;
    report.Error = error;
    return false;
  }
  const bool ok = ReadScene((fs::path(folder.Path()) / FindMainScene(entries)).string(), scene, report, true);
  if (!ok) {
    // Name the scene inside the bundle, not the temporary folder it was unpacked to.
    const std::string temporary = folder.Path() + "/";
    for (size_t at = report.Error.find(temporary); at != std::string::npos; at = report.Error.find(temporary))
      report.Error.erase(at, temporary.size());
    report.Error = "'" + path + "': " + report.Error;
  }
  return ok;
}

}  // namespace rp
