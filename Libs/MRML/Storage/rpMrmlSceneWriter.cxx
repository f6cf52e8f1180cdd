// Writing a vtkRPScene as 3D Slicer's .mrml scene or .mrb bundle (rpMrmlScene.h), the way
// vtkMRMLScene::Commit and vtkMRMLNode::WriteXML write them.
#include <filesystem>
#include <set>
#include <sstream>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkXMLDataElement.h>

#include "rpAtomicFile.h"
#include "rpMrmlBundle.h"
#include "rpMrmlNames.h"
#include "rpMrmlScene.h"
#include "rpMrmlText.h"
#include "rpNodeStorage.h"
#include "rpSceneDataFiles.h"
#include "rpXmlDocument.h"
#include "vtkRPFiducialListNode.h"
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

// One MRML node element to write.
struct XmlNode {
  std::string Tag, ID, Name;
  bool Hidden = true;
  std::string SingletonTag;
  std::map<std::string, std::string> Attributes;
  MrmlReferences References;
  std::string DataFile;  // a storage node's file, as claimed (written first, as `fileName`)
  std::vector<std::pair<std::string, std::string>> Fields;  // in the order written
  void Add(const std::string& key, const std::string& value) { this->Fields.emplace_back(key, value); }
};

// What one of our node classes becomes: the MRML tag, the MRML class (for IDs), our base class.
struct Mapping {
  const char* OurClass;
  const char* Tag;
  const char* MrmlClass;
};
// Most derived first: a segmentation is an image node too, a tracked tool a linear transform.
const Mapping Mappings[] = {
    {"vtkRPSegmentationNode", "Segmentation", "vtkMRMLSegmentationNode"},
    {"vtkRPScalarVolumeNode", "Volume", "vtkMRMLScalarVolumeNode"},
    {"vtkRPModelNode", "Model", "vtkMRMLModelNode"},
    {"vtkRPLinearTransformNode", "LinearTransform", "vtkMRMLLinearTransformNode"},
    {"vtkRPFiducialListNode", "MarkupsFiducial", "vtkMRMLMarkupsFiducialNode"},
    {"vtkRPSliceNode", "Slice", "vtkMRMLSliceNode"},
    {"vtkRPLayoutNode", "Layout", "vtkMRMLLayoutNode"}};

// A scalar volume that came from a Slicer label map goes back as one.
const Mapping LabelMapMapping = {"vtkRPScalarVolumeNode", "LabelMapVolume", "vtkMRMLLabelMapVolumeNode"};

const Mapping* MappingFor(vtkRPNode* node) {
  if (node->IsA("vtkRPScalarVolumeNode") && node->GetAttribute(MrmlLabelMapAttribute) == "true")
    return &LabelMapMapping;
  for (const Mapping& mapping : Mappings)
    if (node->IsA(mapping.OurClass)) return &mapping;
  return nullptr;
}

// Our fields that MRML holds in its own attributes, display nodes or data files; the others
// travel as RoboPlan.<field> attributes.
bool IsMrmlField(const std::string& key) {
  static const std::set<std::string> keys = {
      "ijkToRAS",   "matrixToParent", "color",       "opacity",      "visibility",        "window",
      "level",      "segments",       "layoutName",  "orientation",  "sliceToRAS",        "fieldOfView",
      "xyOrigin",   "sliceVisible",   "foregroundOpacity", "labelOpacity", "viewArrangement",
      "sliceIntersectionVisibility"};
  return keys.count(key) > 0;
}

// The root's list of files an interrupted save left to this scene (SceneDataFiles): ours, not
// Slicer's, which ignores attributes of <MRML> it does not know.
const char* const OwnedFilesAttribute = "roboplanOwnedFiles";

struct WriteContext {
  SceneDataFiles* Files = nullptr;  // where the data files go (under Data/)
  SceneTransferReport* Report = nullptr;
  std::map<std::string, std::string> IDs;  // our ID -> MRML ID
  std::map<std::string, int> Counters;     // MRML class -> last number used
  std::vector<XmlNode> Out;
  std::string NewID(const std::string& mrmlClass) { return mrmlClass + std::to_string(++this->Counters[mrmlClass]); }
  std::string MrmlID(const std::string& ourID) const {
    const auto it = this->IDs.find(ourID);
    return it == this->IDs.end() ? std::string() : it->second;
  }
};

// The main element of a node: ID, name, attributes (ours and our extra fields), transform link.
XmlNode MainElement(WriteContext& context, vtkRPNode* node, const Mapping& mapping) {
  XmlNode element;
  element.Tag = mapping.Tag;
  element.ID = context.MrmlID(node->GetID());
  element.Name = node->GetName();
  element.Hidden = node->GetHideFromEditors();
  for (const auto& [key, value] : node->GetAttributes())
    if (key.rfind(MrmlOwnPrefix, 0) != 0 && key != MrmlLabelMapAttribute) element.Attributes[key] = value;
  vtkRPNode::PropertyMap properties;
  node->WriteProperties(properties);
  for (const auto& [key, value] : properties)
    if (!IsMrmlField(key)) element.Attributes[MrmlOwnPrefix + key] = value;
  if (std::string(node->GetClassName()) != mapping.OurClass) element.Attributes[MrmlOwnClassAttribute] = node->GetClassName();
  const std::string parent = context.MrmlID(node->GetNodeReferenceID(vtkRPTransformableNode::TransformRole()));
  if (!parent.empty()) element.References.push_back({"transform", {parent}});
  return element;
}

// Writes the node's data file under Data/ and adds its storage element. False: reported.
bool AddStorage(WriteContext& context, vtkRPNode* node, XmlNode& main, const std::string& tag,
                const std::string& mrmlClass, const std::string& extension) {
  const std::string fileName = context.Files->Claim("Data", DataFileBaseName(node->GetName()), extension);
  std::string error;
  const NodeStorage* storage = FindNodeStorageForFile(fileName);
  if (!storage || !storage->CanHandle(node)) error = "no writer for " + extension + " files of this node";
  else storage->Write(node, context.Files->StagingPath(fileName), error);
  if (!error.empty()) {
    context.Files->Drop(fileName);
    context.Report->Skipped.push_back({fileName + " (node '" + node->GetName() + "')", error});
    return false;
  }
  context.Report->Files.push_back(fileName);
  XmlNode element;
  element.Tag = tag;
  element.ID = context.NewID(mrmlClass);
  element.DataFile = fileName;
  element.Add("useCompression", "1");
  if (tag == "ModelStorage") element.Add("coordinateSystem", "LPS");  // the .vtk header says so too
  main.References.push_back({"storage", {element.ID}});
  context.Out.push_back(element);
  return true;
}

XmlNode& AddDisplay(WriteContext& context, XmlNode& main, const std::string& tag, const std::string& mrmlClass) {
  XmlNode element;
  element.Tag = tag;
  element.ID = context.NewID(mrmlClass);
  main.References.insert(main.References.begin(), MrmlReferences::value_type("display", std::vector<std::string>{element.ID}));
  context.Out.push_back(element);
  return context.Out.back();
}

std::string Color(const double color[3]) { return FormatNumbers(color, 3); }

bool WriteVolume(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(node);
  if (!AddStorage(context, node, main, "VolumeArchetypeStorage", "vtkMRMLVolumeArchetypeStorageNode", ".nrrd")) return false;
  XmlNode& display = AddDisplay(context, main, "VolumeDisplay", "vtkMRMLScalarVolumeDisplayNode");
  const double window = volume->GetWindow(), level = volume->GetLevel();
  display.Add("window", FormatNumbers(&window, 1));
  display.Add("level", FormatNumbers(&level, 1));
  display.Add("autoWindowLevel", "0");
  display.Add("interpolate", "1");
  display.References.push_back({"colorNodeID", {"vtkMRMLColorTableNodeGrey"}});
  return true;
}

bool WriteLabelMap(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  if (!AddStorage(context, node, main, "VolumeArchetypeStorage", "vtkMRMLVolumeArchetypeStorageNode", ".nrrd")) return false;
  XmlNode& display = AddDisplay(context, main, "LabelMapVolumeDisplay", "vtkMRMLLabelMapVolumeDisplayNode");
  display.References.push_back({"colorNodeID", {"vtkMRMLColorTableNodeLabels"}});  // Slicer's default
  return true;
}

bool WriteSegmentation(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node);
  if (!AddStorage(context, node, main, "SegmentationStorage", "vtkMRMLSegmentationStorageNode", ".seg.nrrd")) return false;
  XmlNode& display = AddDisplay(context, main, "SegmentationDisplay", "vtkMRMLSegmentationDisplayNode");
  display.Add("visibility", "true");
  display.Add("visibility2D", "true");
  display.Add("visibility3D", "true");
  display.Add("PreferredDisplayRepresentationName2D", "Binary labelmap");
  display.Add("PreferredDisplayRepresentationName3D", "Closed surface");
  display.Add("Visibility2DFill", "true");
  display.Add("Visibility2DOutline", "true");
  display.Add("Opacity3D", "1");
  display.Add("Opacity2DFill", "0.5");
  display.Add("Opacity2DOutline", "1");
  // Colours live in the .seg.nrrd (no override here), as Slicer writes them.
  std::string segments;
  for (const auto& segment : segmentation->GetSegments())
    segments += MrmlUrlEncode(segment.ID) +
                " OverrideColorR:-1 OverrideColorG:-1 OverrideColorB:-1 Visible:true Visible3D:true "
                "Visible2DFill:true Visible2DOutline:true Opacity3D:1 Opacity2DFill:1 Opacity2DOutline:1|";
  display.Add("SegmentationDisplayProperties", segments);
  return true;
}

bool WriteModel(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* model = vtkRPModelNode::SafeDownCast(node);
  if (!AddStorage(context, node, main, "ModelStorage", "vtkMRMLModelStorageNode", ".vtk")) return false;
  XmlNode& display = AddDisplay(context, main, "ModelDisplay", "vtkMRMLModelDisplayNode");
  const double opacity = model->GetOpacity();
  display.Add("color", Color(model->GetColor()));
  display.Add("opacity", FormatNumbers(&opacity, 1));
  display.Add("visibility", model->GetVisibility() ? "true" : "false");
  display.Add("visibility2D", model->GetSliceIntersectionVisibility() ? "true" : "false");  // the outline on the slices
  display.Add("visibility3D", "true");
  display.Add("backfaceCulling", "false");
  return true;
}

bool WriteTransform(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* transform = vtkRPLinearTransformNode::SafeDownCast(node);
  double matrix[16];
  vtkMatrix4x4::DeepCopy(matrix, transform->GetMatrixTransformToParent());
  main.Add("matrixTransformToParent", FormatNumbers(matrix, 16));
  return AddStorage(context, node, main, "TransformStorage", "vtkMRMLTransformStorageNode", ".h5");
}

bool WriteFiducials(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* list = vtkRPFiducialListNode::SafeDownCast(node);
  if (!AddStorage(context, node, main, "MarkupsJsonStorage", "vtkMRMLMarkupsJsonStorageNode", ".mrk.json")) return false;
  XmlNode& display = AddDisplay(context, main, "MarkupsFiducialDisplay", "vtkMRMLMarkupsFiducialDisplayNode");
  display.Add("color", Color(list->GetColor()));
  display.Add("selectedColor", Color(list->GetColor()));
  display.Add("visibility", "true");
  return true;
}

bool WriteSlice(WriteContext& context, vtkRPNode* node, XmlNode& main) {
  auto* slice = vtkRPSliceNode::SafeDownCast(node);
  main.SingletonTag = slice->GetLayoutName();
  main.Name = slice->GetLayoutName();  // Slicer names a view's nodes after it ("Red")
  double matrix[16], fov[3] = {slice->GetFieldOfView()[0], slice->GetFieldOfView()[1], 1},
                     origin[3] = {slice->GetXYOrigin()[0], slice->GetXYOrigin()[1], 0};
  vtkNew<vtkMatrix4x4> sliceToRAS;
  slice->GetSliceToRAS(sliceToRAS);
  vtkMatrix4x4::DeepCopy(matrix, sliceToRAS);
  main.Add("fieldOfView", FormatNumbers(fov, 3));
  main.Add("dimensions", "256 256 1");
  main.Add("xyzOrigin", FormatNumbers(origin, 3));
  main.Add("layoutName", slice->GetLayoutName());
  main.Add("sliceToRAS", FormatNumbers(matrix, 16));
  for (const char* preset : {"Axial", "Sagittal", "Coronal"}) {
    double rotation[3][3];
    vtkRPSliceNode::GetOrientationMatrix(preset, rotation);
    main.Add(std::string("orientationMatrix") + preset, FormatNumbers(&rotation[0][0], 9));
  }
  main.Add("orientation", slice->GetOrientation());
  main.Add("defaultOrientation", vtkRPSliceNode::GetDefaultOrientationForLayoutName(slice->GetLayoutName()));
  main.Add("sliceVisibility", slice->GetSliceVisible() ? "true" : "false");
  // The layers: Slicer's SliceComposite node of the same view.
  XmlNode composite;
  composite.Tag = "SliceComposite";
  composite.ID = "vtkMRMLSliceCompositeNode" + slice->GetLayoutName();
  composite.SingletonTag = slice->GetLayoutName();
  composite.Name = slice->GetLayoutName();
  const std::string background = context.MrmlID(slice->GetBackgroundVolumeID()),
                    foreground = context.MrmlID(slice->GetForegroundVolumeID());
  if (!background.empty()) composite.References.push_back({"backgroundVolume", {background}});
  if (!foreground.empty()) composite.References.push_back({"foregroundVolume", {foreground}});
  const double foregroundOpacity = slice->GetForegroundOpacity(), labelOpacity = slice->GetLabelOpacity();
  composite.Add("foregroundOpacity", FormatNumbers(&foregroundOpacity, 1));
  composite.Add("labelOpacity", FormatNumbers(&labelOpacity, 1));
  composite.Add("layoutName", slice->GetLayoutName());
  context.Out.push_back(composite);
  return true;
}

bool WriteLayout(WriteContext&, vtkRPNode* node, XmlNode& main) {
  main.SingletonTag = "vtkMRMLLayoutNode";
  main.Add("currentViewArrangement",
           std::to_string(SlicerLayoutFromArrangement(vtkRPLayoutNode::SafeDownCast(node)->GetViewArrangement())));
  return true;
}

using NodeWriter = bool (*)(WriteContext&, vtkRPNode*, XmlNode&);
NodeWriter WriterFor(const std::string& tag) {
  static const std::map<std::string, NodeWriter> writers = {
      {"Volume", WriteVolume},         {"LabelMapVolume", WriteLabelMap}, {"Segmentation", WriteSegmentation},
      {"Model", WriteModel},
      {"LinearTransform", WriteTransform}, {"MarkupsFiducial", WriteFiducials}, {"Slice", WriteSlice},
      {"Layout", WriteLayout}};
  return writers.at(tag);
}

// Slicer's IDs: "vtkMRMLModelNode1"...; singletons "vtkMRMLSliceNodeRed", "vtkMRMLLayoutNodevtkMRMLLayoutNode".
void AssignIDs(WriteContext& context, vtkRPScene* scene) {
  for (vtkRPNode* node : scene->GetNodes()) {
    const Mapping* mapping = MappingFor(node);
    if (!mapping) continue;
    if (auto* slice = vtkRPSliceNode::SafeDownCast(node)) context.IDs[node->GetID()] = std::string(mapping->MrmlClass) + slice->GetLayoutName();
    else if (vtkRPLayoutNode::SafeDownCast(node)) context.IDs[node->GetID()] = "vtkMRMLLayoutNodevtkMRMLLayoutNode";
    else context.IDs[node->GetID()] = context.NewID(mapping->MrmlClass);
  }
}

// `fileNames`: how the scene names each claimed data file (SceneDataFiles::Commit).
std::string FormatElement(const XmlNode& node, const std::map<std::string, std::string>& fileNames) {
  std::string text = " <" + node.Tag + "\n  id=\"" + MrmlXmlEscape(node.ID) + "\" name=\"" + MrmlXmlEscape(node.Name) +
                     "\" hideFromEditors=\"" + (node.Hidden ? "true" : "false") + "\" selectable=\"true\" selected=\"false\"";
  if (!node.SingletonTag.empty()) text += " singletonTag=\"" + MrmlXmlEscape(node.SingletonTag) + "\"";
  if (!node.Attributes.empty()) text += " attributes=\"" + MrmlXmlEscape(FormatMrmlAttributes(node.Attributes)) + "\"";
  const std::string references = FormatMrmlReferences(node.References);
  if (!references.empty()) text += " references=\"" + MrmlXmlEscape(references) + "\"";
  if (!node.DataFile.empty()) text += " fileName=\"" + MrmlXmlEscape(MrmlUrlEncode(fileNames.at(node.DataFile))) + "\"";
  for (const auto& [key, value] : node.Fields) text += " " + key + "=\"" + MrmlXmlEscape(value) + "\"";
  return text + " ></" + node.Tag + ">\n";
}

std::string FormatScene(const std::vector<XmlNode>& nodes, const std::map<std::string, std::string>& fileNames,
                        const std::vector<std::string>& alsoOwned) {
  std::string owned;
  for (const std::string& name : alsoOwned) owned += (owned.empty() ? "" : " ") + MrmlUrlEncode(name);
  std::string text = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<MRML  version=\"Slicer4.4.0\" userTags=\"\"";
  if (!owned.empty()) text += std::string(" ") + OwnedFilesAttribute + "=\"" + MrmlXmlEscape(owned) + "\"";
  text += ">\n";
  for (const XmlNode& node : nodes) text += FormatElement(node, fileNames);
  return text + "</MRML>\n";
}

// The files a .mrml owns: every storage node's file inside its folder and those its root lists
// (empty when there is none or it cannot be read).
std::set<std::string> OwnedFilesOf(const std::string& path) {
  std::set<std::string> files;
  std::error_code ec;
  std::string error;
  if (!fs::exists(path, ec)) return files;
  vtkSmartPointer<vtkXMLDataElement> root = ReadXmlFile(path, error);
  if (!root) return files;
  if (const char* owned = root->GetAttribute(OwnedFilesAttribute)) {
    std::istringstream names(owned);
    for (std::string name; names >> name;) files.insert(MrmlUrlDecode(name));
  }
  for (int i = 0; i < root->GetNumberOfNestedElements(); ++i)
    if (const char* fileName = root->GetNestedElement(i)->GetAttribute("fileName")) files.insert(MrmlUrlDecode(fileName));
  return files;
}

// The scene's nodes as MRML elements, with their data files written under Data/.
std::vector<XmlNode> BuildScene(vtkRPScene* scene, SceneDataFiles& files, SceneTransferReport& report) {
  WriteContext context;
  context.Files = &files;
  context.Report = &report;
  AssignIDs(context, scene);
  std::map<std::string, int> unmapped;
  for (vtkRPNode* node : scene->GetNodes()) {
    const Mapping* mapping = MappingFor(node);
    if (!mapping) {
      ++unmapped[node->GetNodeTagName()];
      continue;
    }
    XmlNode main = MainElement(context, node, *mapping);
    if (!WriterFor(mapping->Tag)(context, node, main)) continue;
    context.Out.push_back(main);
    ++report.NodesByType[mapping->Tag];
  }
  if (!unmapped.empty()) {
    std::string list;
    for (const auto& [tag, count] : unmapped) list += (list.empty() ? "" : ", ") + tag + " x" + std::to_string(count);
    report.Warnings.push_back("not written, Slicer has no such node types: " + list);
  }
  return context.Out;
}

}  // namespace

bool WriteMrmlScene(vtkRPScene* scene, const std::string& path, SceneTransferReport& report) {
  report = SceneTransferReport();
  const fs::path folder = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder / "Data", ec);
  if (ec) {
    report.Ok = false;
    report.Error = "cannot create folder '" + (folder / "Data").string() + "': " + ec.message();
    return false;
  }
  // Data/ files the previous scene here wrote are replaced; others' are left alone (rpSceneDataFiles.h).
  SceneDataFiles files(folder, OwnedFilesOf(path));
  files.RemoveInterruptedSaves("Data");
  const std::vector<XmlNode> nodes = BuildScene(scene, files, report);
  const auto text = [&nodes](const std::map<std::string, std::string>& names, const std::vector<std::string>& owned) {
    return FormatScene(nodes, names, owned);
  };
  if (!files.Commit(path, text, report.Error)) report.Ok = false;
  return report.Ok;
}

bool WriteMrmlBundle(vtkRPScene* scene, const std::string& path, SceneTransferReport& report) {
  report = SceneTransferReport();
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  // Staged beside the output (nothing written elsewhere), zipped to a temporary name, renamed.
  TemporaryFolder staging(".roboplan-mrb", folder.string());
  std::string root = target.stem().string();
  if (root.empty()) root = "scene";
  if (staging.Path().empty() ||
      !WriteMrmlScene(scene, (fs::path(staging.Path()) / (root + ".mrml")).string(), report)) {
    report.Ok = false;
    if (report.Error.empty()) report.Error = "cannot make a staging folder in '" + folder.string() + "'";
    return false;
  }
  const auto pack = [&](const std::string& temporary, std::string& error) {
    return PackBundle(staging.Path(), root, temporary, error);
  };
  if (!WriteAtomicallyWith(path, pack, report.Error)) report.Ok = false;
  return report.Ok;
}

}  // namespace rp
