// rpSlicerMrmlOracle: what 3D Slicer 5.0.3's own MRML library (vtkMRMLScene, MRMLCore, the Markups
// and Sequences MRML libraries) writes and reads, for RoboPlan's .mrml/.mrb tests. Test-only; built
// with the oracle libraries by Build/CMakeLists.txt, never part of RoboPlan.
//
//   rpSlicerMrmlOracle write-mrb <out.mrb>     a scene written by vtkMRMLScene::WriteToMRB: a CT-like
//       volume (analytic voxels), a labelmap, two models, fiducials under a linear transform under
//       another transform, a segmentation with two segments, node attributes
//   rpSlicerMrmlOracle write-plan <folder>    a plan as Slicer writes it: a markups line ("Tunnel", under a
//       transform, with attributes), a point-normal plane ("Resection") and a 3-point plane
//       ("ThreePoint"), each as its own .mrk.json (Slicer's JSON storage nodes) and all in
//       <folder>/slicer-plan.mrb; prints the values they were built with
//   rpSlicerMrmlOracle load-markups <file.mrk.json>   loads a markups file as Slicer's Markups module
//       does (the storage class its type asks for, AddNewMarkupsNodeFromFile) and prints the node
//   rpSlicerMrmlOracle dump <scene.mrml|.mrb>   loads with vtkMRMLScene::Connect / ReadFromMRB and
//       prints JSON: the errors and warnings MRML logged (vtkOutputWindow and the message
//       collection), and per node its class, ID, name, attributes, references, transforms (to
//       parent, to world), volume geometry and voxel statistics, model points in RAS, display
//       properties, markup control points (local and world), segments.
//
// The scene is set up as Slicer's application logic does (BUILDING-ON-DEBIAN12.md): ITK's IO
// factories, singleton selection and interaction nodes, slice orientation presets, a cache and
// data IO manager, and the scene view, sequence and markups node classes registered. Exit code:
// 0 on success, 1 when the scene or file could not be written or read, 2 on bad usage.
#include <itkFactoryRegistration.h>

#include <vtkBinaryLabelmapToClosedSurfaceConversionRule.h>
#include <vtkCacheManager.h>
#include <vtkClosedSurfaceToBinaryLabelmapConversionRule.h>
#include <vtkClosedSurfaceToFractionalLabelmapConversionRule.h>
#include <vtkFractionalLabelmapToClosedSurfaceConversionRule.h>
#include <vtkMRMLColorTableNode.h>
#include <vtkDataIOManager.h>
#include <vtkMRMLDisplayNode.h>
#include <vtkMRMLDisplayableNode.h>
#include <vtkMRMLInteractionNode.h>
#include <vtkMRMLLabelMapVolumeNode.h>
#include <vtkMRMLLayoutNode.h>
#include <vtkMRMLLinearTransformNode.h>
#include <vtkMRMLMarkupsAngleNode.h>
#include <vtkMRMLMarkupsClosedCurveNode.h>
#include <vtkMRMLMarkupsCurveNode.h>
#include <vtkMRMLMarkupsDisplayNode.h>
#include <vtkMRMLMarkupsFiducialDisplayNode.h>
#include <vtkMRMLMarkupsFiducialNode.h>
#include <vtkMRMLMarkupsFiducialStorageNode.h>
#include <vtkMRMLMarkupsJsonStorageNode.h>
#include <vtkMRMLMarkupsLineNode.h>
#include <vtkMRMLMarkupsPlaneDisplayNode.h>
#include <vtkMRMLMarkupsPlaneJsonStorageNode.h>
#include <vtkMRMLMarkupsPlaneNode.h>
#include <vtkMRMLMarkupsROIDisplayNode.h>
#include <vtkMRMLMarkupsROIJsonStorageNode.h>
#include <vtkMRMLMarkupsROINode.h>
#include <vtkMRMLMessageCollection.h>
#include <vtkMRMLModelDisplayNode.h>
#include <vtkMRMLModelNode.h>
#include <vtkMRMLScalarVolumeDisplayNode.h>
#include <vtkMRMLScalarVolumeNode.h>
#include <vtkMRMLScene.h>
#include <vtkMRMLSceneViewNode.h>
#include <vtkMRMLSegmentationDisplayNode.h>
#include <vtkMRMLSegmentationNode.h>
#include <vtkMRMLSelectionNode.h>
#include <vtkMRMLSequenceBrowserNode.h>
#include <vtkMRMLSliceNode.h>
#include <vtkMRMLStorageNode.h>
#include <vtkMRMLVolumeNode.h>
#include <vtkOrientedImageData.h>
#include <vtkSegment.h>
#include <vtkSegmentation.h>
#include <vtkSegmentationConverter.h>
#include <vtkSegmentationConverterFactory.h>

#include <vtkCubeSource.h>
#include <vtkImageData.h>
#include <vtkLogger.h>
#include <vtkMatrix4x4.h>
#include <vtkVector.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtksys/SystemTools.hxx>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <unistd.h>
#include <vector>

using nlohmann::json;

namespace {

// ---------------------------------------------------------------- what MRML logs
/// Collects VTK's error and warning output (vtkErrorMacro, vtkWarningMacro) instead of printing it.
class rpOracleOutputWindow : public vtkOutputWindow {
 public:
  static rpOracleOutputWindow* New();
  vtkTypeMacro(rpOracleOutputWindow, vtkOutputWindow);
  void DisplayErrorText(const char* text) override { this->Add("error", text); }
  void DisplayWarningText(const char* text) override { this->Add("warning", text); }
  void DisplayGenericWarningText(const char* text) override { this->Add("warning", text); }
  void DisplayText(const char*) override {}  // information (vtkArchive lists what it zips)
  void DisplayDebugText(const char*) override {}
  json Messages = json::array();

 private:
  void Add(const char* type, const char* text) {
    const std::string message = text ? text : "";
    // Debian's VTK 9.1 deprecates vtkPassThroughFilter, which every markups curve node creates
    // (Slicer's VTK does not warn): the one warning filtered.
    if (message.find("vtkPassThroughFilter") != std::string::npos) return;
    this->Messages.push_back({{"type", type}, {"text", message}});
  }
};
vtkStandardNewMacro(rpOracleOutputWindow);

/// Adds the messages of MRML's user-message collection (what Slicer shows in its error dialog).
void AddUserMessages(vtkMRMLMessageCollection* messages, json& out) {
  for (int i = 0; i < messages->GetNumberOfMessages(); ++i) {
    const unsigned long type = messages->GetNthMessageType(i);
    const char* name = type == vtkCommand::ErrorEvent ? "error" : type == vtkCommand::WarningEvent ? "warning" : "text";
    out.push_back({{"type", name}, {"text", messages->GetNthMessageText(i)}});
  }
}

json MessageSummary(const json& messages) {
  int errors = 0, warnings = 0;
  for (const json& m : messages) {
    errors += m["type"] == "error";
    warnings += m["type"] == "warning";
  }
  return {{"errors", errors}, {"warnings", warnings}, {"list", messages}};
}

// ---------------------------------------------------------------- the scene as Slicer sets it up
/// The segmentation converter rules the Segmentations module registers at start-up.
void RegisterSegmentationConverterRules() {
  vtkSegmentationConverterFactory* factory = vtkSegmentationConverterFactory::GetInstance();
  factory->RegisterConverterRule(vtkNew<vtkBinaryLabelmapToClosedSurfaceConversionRule>());
  factory->RegisterConverterRule(vtkNew<vtkClosedSurfaceToBinaryLabelmapConversionRule>());
  factory->RegisterConverterRule(vtkNew<vtkClosedSurfaceToFractionalLabelmapConversionRule>());
  factory->RegisterConverterRule(vtkNew<vtkFractionalLabelmapToClosedSurfaceConversionRule>());
}

/// The built-in colour tables vtkMRMLColorLogic adds to every scene (singletons, not saved,
/// IDs vtkMRMLColorTableNode<type>), and stand-ins with the IDs of the two label colour files
/// Slicer ships (GenericAnatomyColors, GenericColors), which scenes reference.
void AddDefaultColorNodes(vtkMRMLScene* scene) {
  vtkNew<vtkMRMLColorTableNode> types;
  for (int type = types->GetFirstType(); type <= types->GetLastType(); ++type) {
    if (type == vtkMRMLColorTableNode::Obsolete || type == vtkMRMLColorTableNode::File ||
        type == vtkMRMLColorTableNode::User)
      continue;
    vtkNew<vtkMRMLColorTableNode> node;
    node->SetType(type);
    node->SetName(node->GetTypeAsString());
    node->SetSingletonTag(node->GetTypeAsString());
    node->SetSaveWithScene(false);
    scene->AddNode(node);
  }
  for (const char* file : {"GenericAnatomyColors.txt", "GenericColors.txt"}) {
    vtkNew<vtkMRMLColorTableNode> node;
    node->SetTypeToLabels();
    node->SetName(std::string(file).substr(0, std::string(file).size() - 4).c_str());
    node->SetSingletonTag((std::string("File") + file).c_str());
    node->SetSaveWithScene(false);
    scene->AddNode(node);
  }
}

/// A scene as Slicer's application logic prepares it; the cache (where bundles are unpacked and
/// packed) is `cacheDir`.
vtkSmartPointer<vtkMRMLScene> NewSlicerScene(const std::string& cacheDir) {
  auto scene = vtkSmartPointer<vtkMRMLScene>::New();
  vtkNew<vtkCacheManager> cacheManager;
  cacheManager->SetRemoteCacheDirectory(cacheDir.c_str());
  vtkNew<vtkDataIOManager> dataIOManager;
  dataIOManager->SetCacheManager(cacheManager);
  scene->SetCacheManager(cacheManager);
  scene->SetDataIOManager(dataIOManager);
  scene->RegisterNodeClass(vtkNew<vtkMRMLSceneViewNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLSequenceBrowserNode>());
  // The markups module's node classes (vtkSlicerMarkupsLogic::RegisterNodes).
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsFiducialNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsLineNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsAngleNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsCurveNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsClosedCurveNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsPlaneNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsROINode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsDisplayNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsFiducialDisplayNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsPlaneDisplayNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsROIDisplayNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsFiducialStorageNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsJsonStorageNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsPlaneJsonStorageNode>());
  scene->RegisterNodeClass(vtkNew<vtkMRMLMarkupsROIJsonStorageNode>());
  // Singletons (vtkMRMLApplicationLogic::SetMRMLSceneInternal), slice presets, colours.
  scene->AddNode(vtkNew<vtkMRMLSelectionNode>());
  scene->AddNode(vtkNew<vtkMRMLInteractionNode>());
  vtkMRMLSliceNode::AddDefaultSliceOrientationPresets(scene);
  AddDefaultColorNodes(scene);
  return scene;
}

// ---------------------------------------------------------------- write-mrb: the known scene
constexpr int kCtDims[3] = {24, 20, 16};

/// The CT's analytic voxel value (HU-like, short).
short CtValue(int i, int j, int k) { return static_cast<short>(-1000 + 3 * i + 50 * j + 125 * k); }

/// IJK-to-RAS of the CT (and its segmentation): spacing 0.8, 0.9, 1.25 mm, rotated 30 degrees
/// about S, origin (-9.6, 12, -20).
void CtIjkToRas(vtkMatrix4x4* m) {
  vtkNew<vtkTransform> t;
  t->Translate(-9.6, 12.0, -20.0);
  t->RotateZ(30.0);
  t->Scale(0.8, 0.9, 1.25);
  m->DeepCopy(t->GetMatrix());
}

vtkMRMLScalarVolumeNode* AddCt(vtkMRMLScene* scene) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(kCtDims[0], kCtDims[1], kCtDims[2]);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* voxels = static_cast<short*>(image->GetScalarPointer());
  for (int k = 0; k < kCtDims[2]; ++k)
    for (int j = 0; j < kCtDims[1]; ++j)
      for (int i = 0; i < kCtDims[0]; ++i) *voxels++ = CtValue(i, j, k);
  auto* ct = vtkMRMLScalarVolumeNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLScalarVolumeNode", "CT"));
  vtkNew<vtkMatrix4x4> ijkToRas;
  CtIjkToRas(ijkToRas);
  ct->SetIJKToRASMatrix(ijkToRas);
  ct->SetAndObserveImageData(image);
  ct->CreateDefaultDisplayNodes();
  auto* display = vtkMRMLScalarVolumeDisplayNode::SafeDownCast(ct->GetDisplayNode());
  display->SetAutoWindowLevel(0);
  display->SetWindowLevel(400.0, 40.0);
  ct->SetAttribute("Oracle.Content", "analytic CT: -1000 + 3i + 50j + 125k");
  return ct;
}

void AddLabelmap(vtkMRMLScene* scene) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(12, 10, 8);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* voxels = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 12; ++i) *voxels++ = i < 6 ? 1 : (j > 5 ? 2 : 0);
  auto* labels = vtkMRMLLabelMapVolumeNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLLabelMapVolumeNode", "Labels"));
  labels->SetOrigin(5.0, -6.0, 7.5);
  labels->SetSpacing(1.5, 1.5, 2.0);
  labels->SetAndObserveImageData(image);
  labels->CreateDefaultDisplayNodes();
}

vtkMRMLLinearTransformNode* AddTransform(vtkMRMLScene* scene, const char* name, double angle, int axis,
                                         const double translation[3], vtkMRMLTransformNode* parent) {
  auto* node = vtkMRMLLinearTransformNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLLinearTransformNode", name));
  vtkNew<vtkTransform> t;
  t->Translate(translation);
  t->RotateWXYZ(angle, axis == 0, axis == 1, axis == 2);
  node->SetMatrixTransformToParent(t->GetMatrix());
  if (parent) node->SetAndObserveTransformNodeID(parent->GetID());
  return node;
}

vtkMRMLModelNode* AddModel(vtkMRMLScene* scene, const char* name, vtkPolyData* mesh, const double color[3],
                           double opacity) {
  auto* model = vtkMRMLModelNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLModelNode", name));
  model->SetAndObservePolyData(mesh);
  model->CreateDefaultDisplayNodes();
  vtkMRMLDisplayNode* display = model->GetDisplayNode();
  display->SetColor(color[0], color[1], color[2]);
  display->SetOpacity(opacity);
  display->SetVisibility2D(true);  // slice intersections
  return model;
}

void AddModels(vtkMRMLScene* scene, vtkMRMLTransformNode* outer) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(10.0, -5.0, 20.0);
  sphere->SetRadius(15.0);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  sphere->Update();
  const double bone[3] = {0.9, 0.8, 0.6};
  vtkMRMLModelNode* femur = AddModel(scene, "Femur", sphere->GetOutput(), bone, 0.7);
  // What a Slicer user sets for RoboPlan (its tissue class and haptic flag), and one of their own.
  femur->SetAttribute("RoboPlan.tissueClass", "bone");
  femur->SetAttribute("RoboPlan.haptic", "true");
  femur->SetAttribute("Lab.Surgeon", "A. N. Other");
  vtkNew<vtkCubeSource> cube;
  cube->SetBounds(-4.0, 6.0, -3.0, 3.5, 2.0, 12.25);
  cube->Update();
  const double tool[3] = {0.2, 0.4, 1.0};
  vtkMRMLModelNode* drill = AddModel(scene, "Drill", cube->GetOutput(), tool, 1.0);
  drill->SetAndObserveTransformNodeID(outer->GetID());
}

void AddFiducials(vtkMRMLScene* scene, vtkMRMLTransformNode* parent) {
  auto* fiducials = vtkMRMLMarkupsFiducialNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLMarkupsFiducialNode", "F"));
  fiducials->AddControlPoint(1.0, 2.0, 3.0, "F-1");
  fiducials->AddControlPoint(-10.5, 20.25, 7.0, "F-2");
  fiducials->AddControlPoint(30.0, -4.0, -12.125, "F-3");
  fiducials->CreateDefaultDisplayNodes();
  fiducials->GetDisplayNode()->SetSelectedColor(0.2, 0.9, 0.3);
  fiducials->SetAndObserveTransformNodeID(parent->GetID());
  fiducials->SetAttribute("Lab.Role", "landmarks");
}

/// A binary labelmap on the CT's grid: 1 inside the box [lo, hi) of IJK indices.
vtkSmartPointer<vtkOrientedImageData> BoxLabelmap(const int lo[3], const int hi[3]) {
  auto image = vtkSmartPointer<vtkOrientedImageData>::New();
  image->SetDimensions(kCtDims[0], kCtDims[1], kCtDims[2]);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  vtkNew<vtkMatrix4x4> ijkToRas;
  CtIjkToRas(ijkToRas);
  image->SetImageToWorldMatrix(ijkToRas);
  auto* voxels = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < kCtDims[2]; ++k)
    for (int j = 0; j < kCtDims[1]; ++j)
      for (int i = 0; i < kCtDims[0]; ++i)
        *voxels++ = i >= lo[0] && i < hi[0] && j >= lo[1] && j < hi[1] && k >= lo[2] && k < hi[2];
  return image;
}

void AddSegmentation(vtkMRMLScene* scene, vtkMRMLScalarVolumeNode* ct) {
  auto* seg = vtkMRMLSegmentationNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLSegmentationNode", "Segmentation"));
  seg->SetReferenceImageGeometryParameterFromVolumeNode(ct);
  seg->CreateDefaultDisplayNodes();
  const int boneLo[3] = {0, 0, 0}, boneHi[3] = {24, 20, 4};    // 1920 voxels
  const int tumorLo[3] = {10, 8, 6}, tumorHi[3] = {14, 12, 10};  // 64 voxels
  double boneColor[3] = {0.9, 0.85, 0.7}, tumorColor[3] = {1.0, 0.0, 0.0};
  seg->AddSegmentFromBinaryLabelmapRepresentation(BoxLabelmap(boneLo, boneHi), "Bone", boneColor, "Bone");
  seg->AddSegmentFromBinaryLabelmapRepresentation(BoxLabelmap(tumorLo, tumorHi), "Tumor", tumorColor, "Tumor");
  seg->SetAttribute("Lab.Study", "knee 7");
}

int WriteMrb(const std::string& out, const std::string& cacheDir, json& messages) {
  vtkSmartPointer<vtkMRMLScene> scene = NewSlicerScene(cacheDir);
  vtkMRMLScalarVolumeNode* ct = AddCt(scene);
  AddLabelmap(scene);
  const double outerShift[3] = {5.0, -3.0, 12.0}, innerShift[3] = {-7.0, 2.0, 4.5};
  vtkMRMLLinearTransformNode* outer = AddTransform(scene, "Outer", 20.0, 0, outerShift, nullptr);
  vtkMRMLLinearTransformNode* inner = AddTransform(scene, "Inner", 35.0, 2, innerShift, outer);
  AddModels(scene, outer);
  AddFiducials(scene, inner);
  AddSegmentation(scene, ct);
  vtkNew<vtkMRMLMessageCollection> userMessages;
  const bool ok = scene->WriteToMRB(out.c_str(), nullptr, userMessages);
  AddUserMessages(userMessages, messages);
  return ok ? 0 : 1;
}

// ---------------------------------------------------------------- dump
json Matrix(vtkMatrix4x4* m) {
  json values = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) values.push_back(m->GetElement(r, c));
  return values;
}

json Vec(const double* v, int n) { return std::vector<double>(v, v + n); }

json DisplayProperties(vtkMRMLDisplayNode* d) {
  json j = {{"id", d->GetID()}, {"class", d->GetClassName()}, {"color", Vec(d->GetColor(), 3)},
            {"selectedColor", Vec(d->GetSelectedColor(), 3)}, {"opacity", d->GetOpacity()},
            {"visibility", d->GetVisibility()}, {"visibility2D", d->GetVisibility2D()},
            {"visibility3D", d->GetVisibility3D()}};
  if (auto* volume = vtkMRMLScalarVolumeDisplayNode::SafeDownCast(d)) {
    j["window"] = volume->GetWindow();
    j["level"] = volume->GetLevel();
  }
  if (auto* seg = vtkMRMLSegmentationDisplayNode::SafeDownCast(d)) j["opacity3D"] = seg->GetOpacity3D();
  return j;
}

/// Voxel statistics: exact sums for integer voxels, and a position-weighted sum that changes when
/// voxels move (a flip or a permutation of axes).
json VoxelStatistics(vtkImageData* image) {
  const vtkIdType n = image->GetNumberOfPoints() * image->GetNumberOfScalarComponents();
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  double sum = 0, weighted = 0, lo = HUGE_VAL, hi = -HUGE_VAL;
  for (vtkIdType i = 0; i < n; ++i) {
    const double v = scalars->GetComponent(i / scalars->GetNumberOfComponents(), i % scalars->GetNumberOfComponents());
    sum += v;
    weighted += v * static_cast<double>(i % 1009 + 1);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return {{"count", n}, {"sum", sum}, {"weightedSum", weighted}, {"min", n ? lo : 0.0}, {"max", n ? hi : 0.0}};
}

void DumpVolume(vtkMRMLVolumeNode* volume, json& j) {
  vtkNew<vtkMatrix4x4> ijkToRas;
  volume->GetIJKToRASMatrix(ijkToRas);
  j["ijkToRas"] = Matrix(ijkToRas);
  vtkImageData* image = volume->GetImageData();
  if (!image) return;
  int dims[3];
  image->GetDimensions(dims);
  j["dimensions"] = {dims[0], dims[1], dims[2]};
  j["scalarType"] = image->GetScalarTypeAsString();
  j["components"] = image->GetNumberOfScalarComponents();
  j["voxels"] = VoxelStatistics(image);
}

void DumpModel(vtkMRMLModelNode* model, json& j) {
  vtkPointSet* mesh = model->GetMesh();
  if (!mesh) return;
  const vtkIdType n = mesh->GetNumberOfPoints();
  j["meshType"] = mesh->GetClassName();
  j["points"] = n;
  j["cells"] = mesh->GetNumberOfCells();
  if (n == 0) return;
  j["firstPoint"] = Vec(mesh->GetPoint(0), 3);
  j["lastPoint"] = Vec(mesh->GetPoint(n - 1), 3);
  j["bounds"] = Vec(mesh->GetBounds(), 6);
}

void DumpMarkups(vtkMRMLMarkupsNode* markups, json& j) {
  json points = json::array();
  for (int i = 0; i < markups->GetNumberOfControlPoints(); ++i) {
    double world[3];
    markups->GetNthControlPointPositionWorld(i, world);
    points.push_back({{"label", markups->GetNthControlPointLabel(i)},
                      {"position", Vec(markups->GetNthControlPointPosition(i), 3)},
                      {"world", Vec(world, 3)}});
  }
  j["controlPoints"] = points;
}

void DumpSegmentation(vtkMRMLSegmentationNode* node, json& j) {
  vtkSegmentation* segmentation = node->GetSegmentation();
  if (!segmentation) return;
  j["masterRepresentation"] = segmentation->GetMasterRepresentationName();
  auto* display = vtkMRMLSegmentationDisplayNode::SafeDownCast(node->GetDisplayNode());
  json segments = json::array();
  for (const std::string& id : segmentation->GetSegmentIDs()) {
    vtkSegment* segment = segmentation->GetSegment(id);
    json s = {{"id", id}, {"name", segment->GetName() ? segment->GetName() : ""},
              {"color", Vec(segment->GetColor(), 3)}, {"labelValue", segment->GetLabelValue()}};
    auto* labelmap = vtkOrientedImageData::SafeDownCast(
        segment->GetRepresentation(vtkSegmentationConverter::GetBinaryLabelmapRepresentationName()));
    if (labelmap && labelmap->GetPointData()->GetScalars()) {
      vtkDataArray* scalars = labelmap->GetPointData()->GetScalars();
      vtkIdType count = 0;
      for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i) count += scalars->GetTuple1(i) == segment->GetLabelValue();
      s["voxels"] = count;
    }
    if (display) {
      s["visible"] = display->GetSegmentVisibility(id);
      s["opacity3D"] = display->GetSegmentOpacity3D(id);
    }
    segments.push_back(s);
  }
  j["segments"] = segments;
}

json DumpTransformable(vtkMRMLTransformableNode* node, json& j) {
  vtkMRMLTransformNode* parent = node->GetParentTransformNode();
  j["parentTransform"] = parent ? json(parent->GetID()) : json(nullptr);
  if (auto* transform = vtkMRMLTransformNode::SafeDownCast(node)) {
    j["linear"] = transform->IsLinear() != 0;
    if (transform->IsLinear()) {
      vtkNew<vtkMatrix4x4> toParent, toWorld;
      transform->GetMatrixTransformToParent(toParent);
      j["toParent"] = Matrix(toParent);
      if (transform->IsTransformToWorldLinear()) {
        transform->GetMatrixTransformToWorld(toWorld);
        j["toWorld"] = Matrix(toWorld);
      }
    }
  }
  return j;
}

json PlaneGeometry(vtkMRMLMarkupsPlaneNode* plane);

json DumpNode(vtkMRMLNode* node) {
  json j = {{"class", node->GetClassName()}, {"id", node->GetID()}, {"name", node->GetName() ? node->GetName() : ""}};
  json attributes = json::object();
  for (const std::string& name : node->GetAttributeNames()) attributes[name] = node->GetAttribute(name.c_str());
  j["attributes"] = attributes;
  std::vector<std::string> roles;
  node->GetNodeReferenceRoles(roles);
  json references = json::object();
  for (const std::string& role : roles) {
    json ids = json::array();
    for (int i = 0; i < node->GetNumberOfNodeReferences(role.c_str()); ++i) {
      const char* id = node->GetNthNodeReferenceID(role.c_str(), i);
      ids.push_back(id ? id : "");
    }
    if (!ids.empty()) references[role] = ids;
  }
  j["references"] = references;
  if (auto* transformable = vtkMRMLTransformableNode::SafeDownCast(node)) DumpTransformable(transformable, j);
  if (auto* displayable = vtkMRMLDisplayableNode::SafeDownCast(node)) {
    json displays = json::array();
    for (int i = 0; i < displayable->GetNumberOfDisplayNodes(); ++i)
      if (vtkMRMLDisplayNode* d = displayable->GetNthDisplayNode(i)) displays.push_back(DisplayProperties(d));
    j["display"] = displays;
  }
  if (auto* storage = vtkMRMLStorageNode::SafeDownCast(node))
    j["fileName"] = storage->GetFileName() ? vtksys::SystemTools::GetFilenameName(storage->GetFileName()) : "";
  if (auto* volume = vtkMRMLVolumeNode::SafeDownCast(node)) DumpVolume(volume, j);
  if (auto* model = vtkMRMLModelNode::SafeDownCast(node)) DumpModel(model, j);
  if (auto* markups = vtkMRMLMarkupsNode::SafeDownCast(node)) DumpMarkups(markups, j);
  if (auto* line = vtkMRMLMarkupsLineNode::SafeDownCast(node)) j["lineLengthWorld"] = line->GetLineLengthWorld();
  if (auto* plane = vtkMRMLMarkupsPlaneNode::SafeDownCast(node)) j["plane"] = PlaneGeometry(plane);
  if (auto* seg = vtkMRMLSegmentationNode::SafeDownCast(node)) DumpSegmentation(seg, j);
  if (auto* slice = vtkMRMLSliceNode::SafeDownCast(node)) {
    j["orientation"] = slice->GetOrientation();
    j["layoutName"] = slice->GetLayoutName() ? slice->GetLayoutName() : "";
  }
  if (auto* layout = vtkMRMLLayoutNode::SafeDownCast(node)) j["viewArrangement"] = layout->GetViewArrangement();
  return j;
}

// ---------------------------------------------------------------- write-plan: a known plan
vtkMRMLMarkupsLineNode* AddLine(vtkMRMLScene* scene, vtkMRMLTransformNode* parent) {
  auto* line = vtkMRMLMarkupsLineNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLMarkupsLineNode", "Tunnel"));
  line->AddControlPoint(vtkVector3d(10.5, -20.25, 30.125), "entry");
  line->AddControlPoint(vtkVector3d(-5.0, 12.5, -8.75), "target");
  line->CreateDefaultDisplayNodes();
  line->GetDisplayNode()->SetSelectedColor(0.1, 0.7, 0.35);
  line->SetAttribute("RoboPlan.toolDiameterMm", "4.5");
  line->SetAttribute("RoboPlan.intendedTissue", "bone");
  line->SetAttribute("Lab.Note", "planned in Slicer");
  line->SetAndObserveTransformNodeID(parent->GetID());
  return line;
}

vtkMRMLMarkupsPlaneNode* AddPointNormalPlane(vtkMRMLScene* scene) {
  auto* plane = vtkMRMLMarkupsPlaneNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLMarkupsPlaneNode", "Resection"));
  plane->SetPlaneType(vtkMRMLMarkupsPlaneNode::PlaneTypePointNormal);
  plane->SetSizeMode(vtkMRMLMarkupsPlaneNode::SizeModeAbsolute);
  plane->AddControlPoint(vtkVector3d(3.0, -4.0, 25.0), "origin");
  const double normal[3] = {0.2, -0.3, 0.9};
  plane->SetNormal(normal);
  plane->SetSize(80.0, 60.0);
  plane->CreateDefaultDisplayNodes();
  plane->GetDisplayNode()->SetSelectedColor(0.9, 0.5, 0.1);
  plane->SetAttribute("Lab.Note", "tibial resection");
  return plane;
}

vtkMRMLMarkupsPlaneNode* AddThreePointPlane(vtkMRMLScene* scene) {
  auto* plane = vtkMRMLMarkupsPlaneNode::SafeDownCast(scene->AddNewNodeByClass("vtkMRMLMarkupsPlaneNode", "ThreePoint"));
  plane->SetPlaneType(vtkMRMLMarkupsPlaneNode::PlaneType3Points);
  plane->AddControlPoint(vtkVector3d(-10.0, 5.0, 40.0));
  plane->AddControlPoint(vtkVector3d(20.0, 8.0, 42.0));
  plane->AddControlPoint(vtkVector3d(-6.0, 30.0, 36.0));
  plane->CreateDefaultDisplayNodes();
  return plane;
}

/// Writes one markups node to its own .mrk.json with the storage class Slicer uses for it.
bool WriteMarkupsFile(vtkMRMLScene* scene, vtkMRMLMarkupsNode* node, const std::string& path) {
  vtkSmartPointer<vtkMRMLMarkupsJsonStorageNode> storage;
  if (vtkMRMLMarkupsPlaneNode::SafeDownCast(node)) storage = vtkSmartPointer<vtkMRMLMarkupsPlaneJsonStorageNode>::New();
  else storage = vtkSmartPointer<vtkMRMLMarkupsJsonStorageNode>::New();
  scene->AddNode(storage);
  storage->SetFileName(path.c_str());
  const bool ok = storage->WriteData(node) != 0;
  scene->RemoveNode(storage);
  return ok;
}

json PlaneGeometry(vtkMRMLMarkupsPlaneNode* plane) {
  double origin[3], normal[3], x[3], y[3], z[3], originWorld[3], normalWorld[3];
  plane->GetOrigin(origin);
  plane->GetNormal(normal);
  plane->GetAxes(x, y, z);
  plane->GetOriginWorld(originWorld);
  plane->GetNormalWorld(normalWorld);
  return {{"planeType", vtkMRMLMarkupsPlaneNode::GetPlaneTypeAsString(plane->GetPlaneType())},
          {"origin", Vec(origin, 3)}, {"normal", Vec(normal, 3)}, {"xAxis", Vec(x, 3)},
          {"originWorld", Vec(originWorld, 3)}, {"normalWorld", Vec(normalWorld, 3)},
          {"size", Vec(plane->GetSize(), 2)}};
}

int WritePlan(const std::string& folder, const std::string& cacheDir, json& messages, json& written) {
  vtkSmartPointer<vtkMRMLScene> scene = NewSlicerScene(cacheDir);
  const double shift[3] = {2.0, -1.5, 4.0};
  vtkMRMLLinearTransformNode* planToCt = AddTransform(scene, "PlanToCT", 15.0, 1, shift, nullptr);
  vtkMRMLMarkupsLineNode* line = AddLine(scene, planToCt);
  vtkMRMLMarkupsPlaneNode* plane = AddPointNormalPlane(scene);
  vtkMRMLMarkupsPlaneNode* threePoint = AddThreePointPlane(scene);
  vtksys::SystemTools::MakeDirectory(folder);
  bool ok = WriteMarkupsFile(scene, line, folder + "/slicer-line.mrk.json") &&
            WriteMarkupsFile(scene, plane, folder + "/slicer-plane.mrk.json") &&
            WriteMarkupsFile(scene, threePoint, folder + "/slicer-plane-3points.mrk.json");
  json threePointNode = DumpNode(threePoint);
  // The bundle holds the line and the point-normal plane (RoboPlan's cut plane is point-normal:
  // a 3-point plane is read as one, its three points become the origin).
  scene->RemoveNode(threePoint);
  vtkNew<vtkMRMLMessageCollection> userMessages;
  ok = scene->WriteToMRB((folder + "/slicer-plan.mrb").c_str(), nullptr, userMessages) && ok;
  AddUserMessages(userMessages, messages);
  written = json::array();
  written.push_back(DumpNode(line));
  written.push_back(DumpNode(plane));
  written.push_back(threePointNode);
  return ok ? 0 : 1;
}

/// A .mrk.json loaded as Slicer's Markups module loads it (vtkSlicerMarkupsLogic::LoadMarkupsFromJson):
/// the storage class the file's type needs, then AddNewMarkupsNodeFromFile.
int LoadMarkups(const std::string& path, const std::string& cacheDir, json& messages, json& nodes) {
  vtkSmartPointer<vtkMRMLScene> scene = NewSlicerScene(cacheDir);
  vtkNew<vtkMRMLMarkupsJsonStorageNode> probe;
  std::vector<std::string> types;
  probe->GetMarkupsTypesInFile(path.c_str(), types);
  if (types.empty()) return 1;
  vtkSmartPointer<vtkMRMLMarkupsJsonStorageNode> storage;
  if (types[0] == "Plane") storage = vtkSmartPointer<vtkMRMLMarkupsPlaneJsonStorageNode>::New();
  else if (types[0] == "ROI") storage = vtkSmartPointer<vtkMRMLMarkupsROIJsonStorageNode>::New();
  else storage = vtkSmartPointer<vtkMRMLMarkupsJsonStorageNode>::New();
  scene->AddNode(storage);
  vtkMRMLMarkupsNode* node = storage->AddNewMarkupsNodeFromFile(path.c_str());
  AddUserMessages(storage->GetUserMessages(), messages);
  if (!node) return 1;
  nodes.push_back(DumpNode(node));
  return 0;
}

int Dump(const std::string& path, const std::string& cacheDir, json& messages, json& nodes) {
  vtkSmartPointer<vtkMRMLScene> scene = NewSlicerScene(cacheDir);
  vtkNew<vtkMRMLMessageCollection> userMessages;
  const std::string extension = vtksys::SystemTools::LowerCase(vtksys::SystemTools::GetFilenameLastExtension(path));
  bool ok;
  if (extension == ".mrb" || extension == ".zip") {
    ok = scene->ReadFromMRB(path.c_str(), /*clear=*/true, userMessages);
  } else {
    scene->SetURL(path.c_str());
    ok = scene->Connect(userMessages) != 0;
  }
  AddUserMessages(userMessages, messages);
  for (int i = 0; i < scene->GetNumberOfNodes(); ++i) nodes.push_back(DumpNode(scene->GetNthNode(i)));
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc == 3 ? argv[1] : "";
  if (command != "write-mrb" && command != "dump" && command != "write-plan" && command != "load-markups") {
    std::cerr << "usage: rpSlicerMrmlOracle write-mrb <out.mrb> | dump <scene.mrml|scene.mrb> | write-plan <folder> | "
                 "load-markups <file.mrk.json>\n";
    return 2;
  }
  itk::itkFactoryRegistration();
  RegisterSegmentationConverterRules();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);  // everything goes through the output window
  vtkNew<rpOracleOutputWindow> output;
  vtkOutputWindow::SetInstance(output);
  const std::string tmp = vtksys::SystemTools::GetEnv("TMPDIR") ? vtksys::SystemTools::GetEnv("TMPDIR") : "/tmp";
  const std::string cacheDir = tmp + "/rpSlicerMrmlOracle-" + std::to_string(getpid());
  vtksys::SystemTools::MakeDirectory(cacheDir);
  json result = {{"command", command}, {"file", argv[2]}};
  json messages = json::array();
  json nodes = json::array();
  const std::string path = vtksys::SystemTools::CollapseFullPath(argv[2]);  // ReadFromMRB needs it absolute
  int rc = 1;
  if (command == "write-mrb") rc = WriteMrb(path, cacheDir, output->Messages);
  else if (command == "dump") rc = Dump(path, cacheDir, output->Messages, nodes);
  else if (command == "write-plan") rc = WritePlan(path, cacheDir, output->Messages, nodes);
  else rc = LoadMarkups(path, cacheDir, output->Messages, nodes);
  vtksys::SystemTools::RemoveADirectory(cacheDir);
  for (const json& m : output->Messages) messages.push_back(m);
  result["ok"] = rc == 0;
  result["messages"] = MessageSummary(messages);
  if (command != "write-mrb") result["nodes"] = nodes;
  std::cout << result.dump(1) << "\n";
  vtkOutputWindow::SetInstance(nullptr);
  return rc;
}
