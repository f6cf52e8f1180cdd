#include "qRPSegmentationToMeshPanel.h"

#include <algorithm>
#include <array>

#include <QApplication>
#include <QFileDialog>
#include <QProgressDialog>
#include <QSignalBlocker>

#include <vtkCommand.h>
#include <vtkPolyData.h>

#include "rpBoneSplit.h"
#include "rpMaterial.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSegmentationToMeshLogic.h"

namespace {

// Busy cursor for short edits; a modal progress dialog (shown after 0.5 s) for meshing. Both run
// on the GUI thread: the dialog's setValue keeps the window painting while the work reports.
class BusyScope {
 public:
  explicit BusyScope(QWidget* panel) : Panel(panel) {
    QApplication::setOverrideCursor(Qt::WaitCursor);
    this->Panel->setEnabled(false);
  }
  ~BusyScope() {
    this->Panel->setEnabled(true);
    QApplication::restoreOverrideCursor();
  }
  BusyScope(const BusyScope&) = delete;
  BusyScope& operator=(const BusyScope&) = delete;

 private:
  QWidget* Panel;
};

class ProgressScope {
 public:
  ProgressScope(QWidget* parent, const QString& label) : Busy(parent), Dialog(label, QString(), 0, 1000, parent) {
    this->Dialog.setWindowModality(Qt::WindowModal);
    this->Dialog.setMinimumDuration(500);
    this->Dialog.setAutoClose(true);
  }
  rp::ProgressCallback Callback() {
    return [this](double fraction, const std::string& message) {
      this->Dialog.setLabelText(QString::fromStdString(message));
      this->Dialog.setValue(std::clamp(static_cast<int>(fraction * 1000), 0, 999));
    };
  }
  ~ProgressScope() { this->Dialog.setValue(1000); }
  ProgressScope(const ProgressScope&) = delete;
  ProgressScope& operator=(const ProgressScope&) = delete;

 private:
  BusyScope Busy;
  QProgressDialog Dialog;
};

void FillNodeCombo(QComboBox* combo, const std::vector<vtkRPNode*>& nodes, const QString& noneText) {
  const QString current = combo->currentData().toString();
  const QSignalBlocker block(combo);
  combo->clear();
  if (!noneText.isEmpty()) combo->addItem(noneText, QString());
  for (vtkRPNode* node : nodes)
    combo->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  const int index = combo->findData(current);
  combo->setCurrentIndex(index >= 0 ? index : (combo->count() > 0 ? 0 : -1));
}

QString StatsText(const QString& name, const rp::MeshStats& s) {
  QString text = QString("%1: %2 voxels, %3 triangles, volume error %4 %, %5")
                     .arg(name)
                     .arg(s.LabelVoxels)
                     .arg(s.Triangles)
                     .arg(s.VolumeErrorPercent, 0, 'f', 2)
                     .arg(s.Watertight ? "watertight" : "NOT watertight");
  for (const auto& w : s.Warnings) text += "\n" + QString::fromStdString(w);
  return text;
}

QString Text(const std::string& text) { return QString::fromStdString(text); }

}  // namespace

qRPSegmentationToMeshPanel::qRPSegmentationToMeshPanel(vtkRPSegmentationToMeshLogic* logic, QWidget* parent)
    : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  this->FillChoices();
  this->ConnectWidgets();
  if (vtkRPScene* scene = this->Logic->GetScene()) {
    const unsigned long events[4] = {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeRemovedEvent,
                                     vtkRPScene::EndImportEvent, vtkRPScene::EndCloseEvent};
    for (int i = 0; i < 4; ++i)
      this->SceneObservers[i] = scene->AddObserver(events[i], this, &qRPSegmentationToMeshPanel::OnSceneEvent);
  }
  this->OnPresetChanged();
  this->OnMethodChanged();
  this->RefreshNodeCombos();
}

// The choices that come from tables: the threshold presets and the tissue classes.
void qRPSegmentationToMeshPanel::FillChoices() {
  for (const auto& preset : rp::ThresholdPresets()) this->PresetCombo->addItem(Text(preset.Name));
  // Tissue classes are the material table's (Resources/Materials/materials.json), so every class
  // offered here has haptic properties.
  rp::MaterialTable materials;
  std::string materialsError;
  if (rp::LoadMaterialTable(materials, materialsError))
    for (const std::string& tissue : materials.TissueNames()) this->TissueCombo->addItem(Text(tissue));
  else
    this->TissueCombo->setToolTip(Text(materialsError));
}

void qRPSegmentationToMeshPanel::ConnectWidgets() {
  connect(this->NewSegmentationButton, &QPushButton::clicked, this, [this] { this->NewSegmentation(); });
  connect(this->LabelTableBrowseButton, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, "Label table", QString(),
                                                      "Label tables (*.ctbl *.txt *.label);;All files (*)");
    if (!path.isEmpty()) this->LabelTableEdit->setText(path);
  });
  connect(this->LabelmapButton, &QPushButton::clicked, this, [this] { this->LabelmapToSegments(); });
  connect(this->SegmentationCombo, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
          [this] { this->RefreshSegments(); });
  connect(this->MethodCombo, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
          [this] { this->OnMethodChanged(); });
  connect(this->PresetCombo, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
          [this] { this->OnPresetChanged(); });
  connect(this->ApplyButton, &QPushButton::clicked, this, [this] { this->Apply(); });
  connect(this->SplitBonesButton, &QPushButton::clicked, this, [this] { this->SplitBones(); });
  connect(this->ClosingButton, &QPushButton::clicked, this, [this] { this->ApplyMorphology(rp::Morphology::Closing); });
  connect(this->OpeningButton, &QPushButton::clicked, this, [this] { this->ApplyMorphology(rp::Morphology::Opening); });
  connect(this->FillHolesButton, &QPushButton::clicked, this,
          [this] { this->ApplyMorphology(rp::Morphology::FillHoles); });
  connect(this->KeepLargestButton, &QPushButton::clicked, this, [this] { this->KeepLargest(); });
  connect(this->PreviewButton, &QPushButton::clicked, this, [this] { this->Preview(); });
  connect(this->CreateModelsButton, &QPushButton::clicked, this, [this] { this->CreateModels(); });
}

qRPSegmentationToMeshPanel::~qRPSegmentationToMeshPanel() {
  this->ObserveSegmentation(nullptr);
  vtkRPScene* scene = this->Logic->GetScene();
  if (!scene) return;
  for (unsigned long tag : this->SceneObservers)
    if (tag) scene->RemoveObserver(tag);
  this->Logic->RemovePreview();  // temporary: never outlives the panel
}

void qRPSegmentationToMeshPanel::OnSceneEvent(vtkObject*, unsigned long event, void* callData) {
  if (this->Logic->GetScene()->IsImporting() && event == vtkRPScene::NodeAddedEvent) return;  // EndImportEvent refreshes
  if (event == vtkRPScene::NodeAddedEvent || event == vtkRPScene::NodeRemovedEvent) {
    auto* node = static_cast<vtkRPNode*>(callData);
    if (node && !node->IsA("vtkRPScalarVolumeNode") && !node->IsA("vtkRPSegmentationNode") &&
        !node->IsA("vtkRPFiducialListNode"))
      return;  // models (ours included) do not change the combos
  }
  this->RefreshNodeCombos();
}

void qRPSegmentationToMeshPanel::RefreshNodeCombos() {
  vtkRPScene* scene = this->Logic->GetScene();
  if (!scene) return;
  FillNodeCombo(this->VolumeCombo, scene->GetNodesByClass("vtkRPScalarVolumeNode"), QString());
  FillNodeCombo(this->SegmentationCombo, scene->GetNodesByClass("vtkRPSegmentationNode"), QString());
  FillNodeCombo(this->SeedsCombo, scene->GetNodesByClass("vtkRPFiducialListNode"), "(no seeds)");
  this->RefreshSegments();
}

void qRPSegmentationToMeshPanel::ObserveSegmentation(vtkRPSegmentationNode* segmentation) {
  if (segmentation == this->ObservedSegmentation) return;
  if (this->ObservedSegmentation && this->SegmentationObserver)
    this->ObservedSegmentation->RemoveObserver(this->SegmentationObserver);
  this->SegmentationObserver = 0;
  this->ObservedSegmentation = segmentation;
  if (segmentation)
    this->SegmentationObserver = segmentation->AddObserver(vtkCommand::ModifiedEvent, this,
                                                           &qRPSegmentationToMeshPanel::OnSegmentationModified);
}

void qRPSegmentationToMeshPanel::OnSegmentationModified(vtkObject*, unsigned long, void*) { this->RefreshSegments(); }

void qRPSegmentationToMeshPanel::RefreshSegments(const std::string& select) {
  this->ObserveSegmentation(this->CurrentSegmentation());
  const QString keep = select.empty() ? this->SegmentCombo->currentData().toString() : Text(select);
  const QSignalBlocker block(this->SegmentCombo);
  this->SegmentCombo->clear();
  if (vtkRPSegmentationNode* segmentation = this->CurrentSegmentation())
    for (const auto& s : segmentation->GetSegments())
      this->SegmentCombo->addItem(Text(s.Name.empty() ? s.ID : s.Name), Text(s.ID));
  const int index = this->SegmentCombo->findData(keep);
  this->SegmentCombo->setCurrentIndex(index >= 0 ? index : (this->SegmentCombo->count() > 0 ? 0 : -1));
}

void qRPSegmentationToMeshPanel::SelectSegmentation(vtkRPSegmentationNode* segmentation) {
  this->SegmentationCombo->setCurrentIndex(this->SegmentationCombo->findData(Text(segmentation->GetID())));
  this->RefreshSegments();
}

void qRPSegmentationToMeshPanel::OnPresetChanged() {
  const rp::ThresholdPreset* preset = rp::FindThresholdPreset(this->PresetCombo->currentText().toStdString());
  if (!preset) return;
  this->LowerSpin->setValue(preset->Lower);
  this->UpperSpin->setValue(preset->Upper);
  this->SegmentNameEdit->setText(Text(preset->Name));
  this->TissueCombo->setCurrentText(Text(preset->TissueClass));
}

void qRPSegmentationToMeshPanel::OnMethodChanged() {
  const int method = this->MethodCombo->currentIndex();
  this->LowerSpin->setEnabled(method == ManualThreshold || method == RegionGrowing);
  this->UpperSpin->setEnabled(method == ManualThreshold || method == RegionGrowing);
  this->SeedsCombo->setEnabled(method == RegionGrowing || method == ConfidenceConnected);
  this->MultiplierSpin->setEnabled(method == ConfidenceConnected);
  this->IterationsSpin->setEnabled(method == ConfidenceConnected);
}

vtkRPScalarVolumeNode* qRPSegmentationToMeshPanel::CurrentVolume() const {
  vtkRPScene* scene = this->Logic->GetScene();
  return scene ? vtkRPScalarVolumeNode::SafeDownCast(
                     scene->GetNodeByID(this->VolumeCombo->currentData().toString().toStdString()))
               : nullptr;
}

vtkRPSegmentationNode* qRPSegmentationToMeshPanel::CurrentSegmentation() const {
  vtkRPScene* scene = this->Logic->GetScene();
  return scene ? vtkRPSegmentationNode::SafeDownCast(
                     scene->GetNodeByID(this->SegmentationCombo->currentData().toString().toStdString()))
               : nullptr;
}

std::string qRPSegmentationToMeshPanel::CurrentSegmentID() const {
  return this->SegmentCombo->currentData().toString().toStdString();
}

std::string qRPSegmentationToMeshPanel::PreviewNodeID() const { return this->Logic->GetPreviewNodeID(); }

QString qRPSegmentationToMeshPanel::StatusText() const { return this->StatusLabel->text(); }

void qRPSegmentationToMeshPanel::ShowError(const QString& text) {
  this->Error = true;
  this->StatusLabel->setStyleSheet("color: red;");
  this->StatusLabel->setText(text);
}

void qRPSegmentationToMeshPanel::ShowStatus(const QString& text) {
  this->Error = false;
  this->StatusLabel->setStyleSheet(QString());
  this->StatusLabel->setText(text);
}

vtkRPSegmentationNode* qRPSegmentationToMeshPanel::NewSegmentation() {
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  vtkRPSegmentationNode* segmentation =
      this->Logic->AddSegmentation(volume ? volume->GetName() + " segmentation" : std::string("Segmentation"));
  if (segmentation) this->SelectSegmentation(segmentation);  // the scene observer filled the combo
  return segmentation;
}

bool qRPSegmentationToMeshPanel::SplitBones() {
  rp::BoneSplitOptions options;
  vtkRPScene* scene = this->Logic->GetScene();
  if (auto* list = vtkRPFiducialListNode::SafeDownCast(
          scene ? scene->GetNodeByID(this->SeedsCombo->currentData().toString().toStdString()) : nullptr)) {
    for (int i = 0; i < list->GetNumberOfControlPoints(); ++i) {
      rp::BoneSeed seed;
      list->GetNthControlPointPositionWorld(i, seed.RAS.data());
      // Only labels a user gave name bones (not the generated "<list>-<n>").
      const std::string& label = list->GetNthControlPoint(i).Label;
      seed.Name = list->IsGeneratedLabel(label) ? "" : label;
      options.Seeds.push_back(seed);
    }
  }
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  rp::BoneSplitResult result;
  std::string error;
  vtkRPSegmentationNode* segmentation = nullptr;
  {
    ProgressScope progress(this, "Bones one by one");
    segmentation = this->Logic->SplitBones(volume, options, volume ? volume->GetName() + " bones" : std::string(),
                                           result, error, progress.Callback());
  }
  if (!segmentation) {
    this->ShowError((volume ? "Bones one by one failed: " : "Bones one by one: ") + Text(error));
    return false;
  }
  this->SelectSegmentation(segmentation);
  QStringList lines;
  for (const auto& b : result.Bones)
    lines << QString("%1: %2 ml%3")
                 .arg(Text(b.ID))
                 .arg(b.VolumeMl, 0, 'f', 1)
                 .arg(b.NamedBy.empty() ? QString() : " (named by " + Text(b.NamedBy) + ")");
  lines << QString("%1 touching pair(s) split; dropped %2 speck(s), %3 piece(s) outside the body")
               .arg(result.Splits)
               .arg(result.DroppedSpecks)
               .arg(result.DroppedOutsideBody);
  for (const auto& note : result.Notes) lines << Text(note);
  this->ShowStatus(lines.join("\n"));
  return true;
}

bool qRPSegmentationToMeshPanel::LabelmapToSegments() {
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  if (!volume || !volume->GetImageData()) {
    this->ShowError("Labelmap: pick an input volume");
    return false;
  }
  rp::LabelTable table;
  std::string error;
  const std::string tablePath = this->LabelTableEdit->text().trimmed().toStdString();
  if (!tablePath.empty() && !rp::ReadLabelTable(tablePath, table, error)) {
    this->ShowError("Labelmap: " + Text(error));
    return false;
  }
  vtkRPSegmentationNode* segmentation = nullptr;
  {
    BusyScope busy(this);
    // The segmentation is edited; the volume stays as loaded.
    segmentation = this->Logic->SegmentationFromLabelmap(volume, tablePath.empty() ? nullptr : &table,
                                                         volume->GetName() + " segments", true, error);
  }
  if (!segmentation) {
    this->ShowError("Labelmap: '" + Text(volume->GetName()) + "': " + Text(error));
    return false;
  }
  this->SelectSegmentation(segmentation);
  QStringList names;
  for (const auto& s : segmentation->GetSegments()) names << Text(s.Name);
  this->ShowStatus(QString("%1 segment(s) from the labelmap '%2': %3")
                       .arg(segmentation->GetNumberOfSegments())
                       .arg(Text(volume->GetName()))
                       .arg(names.join(", ")));
  return true;
}

bool qRPSegmentationToMeshPanel::Recipe(rp::TissueRecipe& recipe, QString& error) const {
  rp::SegmentTarget& target = recipe.Target;
  target.Name = this->SegmentNameEdit->text().trimmed().toStdString();
  target.ID = target.Name;
  target.TissueClass = this->TissueCombo->currentText().trimmed().toStdString();
  const rp::ThresholdPreset* preset = rp::FindThresholdPreset(this->PresetCombo->currentText().toStdString());
  if (preset) target.Color = preset->Color;
  if (vtkRPSegmentationNode* segmentation = this->CurrentSegmentation())
    if (const auto* existing = segmentation->GetSegmentByID(target.ID))
      target.Color = {existing->Color[0], existing->Color[1], existing->Color[2]};  // keep the user's colour
  if (target.ID.empty()) {
    error = "give the segment a name";
    return false;
  }
  const int method = this->MethodCombo->currentIndex();
  rp::SegmentMethod& how = recipe.Method;
  how.Method = method == RegionGrowing         ? rp::SegmentMethod::RegionGrow
               : method == ConfidenceConnected ? rp::SegmentMethod::ConfidenceConnected
                                               : rp::SegmentMethod::Threshold;
  how.Lower = method == PresetThreshold && preset ? preset->Lower : this->LowerSpin->value();
  how.Upper = method == PresetThreshold && preset ? preset->Upper : this->UpperSpin->value();
  how.Multiplier = this->MultiplierSpin->value();
  how.Iterations = this->IterationsSpin->value();
  if (method == RegionGrowing || method == ConfidenceConnected) {
    vtkRPScene* scene = this->Logic->GetScene();
    auto* list = vtkRPFiducialListNode::SafeDownCast(
        scene ? scene->GetNodeByID(this->SeedsCombo->currentData().toString().toStdString()) : nullptr);
    for (int i = 0; list && i < list->GetNumberOfControlPoints(); ++i) {
      std::array<double, 3> p{};
      list->GetNthControlPointPositionWorld(i, p.data());
      how.Seeds.push_back(p);
    }
    if (how.Seeds.empty()) {
      error = this->MethodCombo->currentText() + " needs seeds: pick a fiducial list with at least one point";
      return false;
    }
  }
  return true;
}

bool qRPSegmentationToMeshPanel::Apply() {
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  if (!volume) {
    this->ShowError("Apply: pick an input volume");
    return false;
  }
  rp::TissueRecipe recipe;
  QString problem;
  if (!this->Recipe(recipe, problem)) {
    this->ShowError("Apply: " + problem);
    return false;
  }
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  if (!segmentation) segmentation = this->NewSegmentation();
  std::vector<rp::TissueStep> steps;
  std::string error;
  bool ok = false;
  {
    BusyScope busy(this);
    ok = this->Logic->SegmentTissue(volume, segmentation, recipe, steps, error);
  }
  if (!ok) {
    this->ShowError(QString("Apply failed: ") + Text(error));
    return false;
  }
  this->RefreshSegments(recipe.Target.ID);
  this->ShowStatus(QString("%1: %2 voxels (%3 % of the volume)")
                       .arg(Text(recipe.Target.Name))
                       .arg(steps.back().Result.Voxels)
                       .arg(100.0 * steps.back().Result.Fraction, 0, 'f', 2));
  return true;
}

bool qRPSegmentationToMeshPanel::Edit(int edit, const QString& what) {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  const std::string id = this->CurrentSegmentID();
  if (!segmentation || id.empty()) {
    this->ShowError(what + ": no segment selected (Apply a segmentation first)");
    return false;
  }
  rp::SegmentEdit step;
  step.Edit = static_cast<rp::SegmentEdit::Kind>(edit);
  step.RadiusMm = this->MorphologyRadiusSpin->value();
  rp::EditResult result;
  std::string error;
  bool ok = false;
  {
    BusyScope busy(this);
    ok = this->Logic->EditSegment(segmentation, id, step, result, error);
  }
  if (!ok) {
    this->ShowError(what + " failed: " + Text(error));
    return false;
  }
  if (step.Edit == rp::SegmentEdit::KeepLargest)
    this->ShowStatus(QString("%1: kept the largest of %2 components, %3 voxels")
                         .arg(Text(id))
                         .arg(result.Components)
                         .arg(result.Voxels));
  else
    this->ShowStatus(QString("%1: %2 voxels").arg(Text(id)).arg(result.Voxels));
  return true;
}

bool qRPSegmentationToMeshPanel::ApplyMorphology(rp::Morphology op) {
  const rp::SegmentEdit::Kind edit = op == rp::Morphology::Closing   ? rp::SegmentEdit::Closing
                                     : op == rp::Morphology::Opening ? rp::SegmentEdit::Opening
                                                                     : rp::SegmentEdit::FillHoles;
  return this->Edit(edit, "Morphology");
}

bool qRPSegmentationToMeshPanel::KeepLargest() { return this->Edit(rp::SegmentEdit::KeepLargest, "Keep largest"); }

rp::ModelBuildOptions qRPSegmentationToMeshPanel::BuildOptions() const {
  rp::ModelBuildOptions options;
  const rp::MeshMethod methods[4] = {rp::MeshMethod::Gaussian, rp::MeshMethod::WindowedSinc,
                                     rp::MeshMethod::SlicerDefault, rp::MeshMethod::Discrete};
  options.Display.Method = methods[std::clamp(this->MeshMethodCombo->currentIndex(), 0, 3)];
  options.Display.Sigma = this->SigmaSpin->value();
  for (double& step : options.Display.GridStep) step = this->GridStepSpin->value();
  options.DisplayLOD.TargetTriangles = this->DisplayTrianglesSpin->value();
  options.Haptic = options.Display;
  options.Haptic.DecimationFraction = 0;
  options.HapticLOD.TargetTriangles = this->HapticTrianglesSpin->value();
  options.HapticLOD.MaxErrorMm = 0;
  options.MakeHaptic = this->HapticTrianglesSpin->value() > 0;
  return options;
}

bool qRPSegmentationToMeshPanel::Preview() {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  const std::string id = this->CurrentSegmentID();
  const auto* segment = segmentation ? segmentation->GetSegmentByID(id) : nullptr;
  if (!segment) {
    this->ShowError("Preview: no segment selected (Apply a segmentation first)");
    return false;
  }
  const std::string name = segment->Name.empty() ? segment->ID : segment->Name;
  rp::MeshStats stats;
  std::string error;
  bool ok = false;
  {
    ProgressScope progress(this, "Meshing " + Text(id));
    ok = this->Logic->PreviewSegment(segmentation, id, this->BuildOptions(), stats, error, progress.Callback());
  }
  if (!ok) {
    this->ShowError(QString("Preview failed: ") + Text(error));
    return false;
  }
  this->ShowStatus("Preview " + StatsText(Text(name), stats));
  return true;
}

bool qRPSegmentationToMeshPanel::CreateModels() {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  if (!segmentation || segmentation->GetNumberOfSegments() == 0) {
    this->ShowError("Create models: the segmentation has no segments (Apply a segmentation first)");
    return false;
  }
  rp::ModelBuildOptions options = this->BuildOptions();
  if (!this->AllSegmentsCheck->isChecked()) {
    if (this->CurrentSegmentID().empty()) {
      this->ShowError("Create models: no segment selected");
      return false;
    }
    options.SegmentIDs = {this->CurrentSegmentID()};
  }
  std::vector<rp::SegmentModels> models;
  {
    ProgressScope progress(this, "Creating models");
    models = this->Logic->CreateModels(segmentation, options, progress.Callback());
  }
  QStringList lines, errors;
  for (const auto& m : models) {
    if (!m.Ok) {
      errors << Text(m.Error);
      continue;
    }
    QString line = StatsText(Text(m.Name), m.Display);
    if (m.HapticModel)
      line += QString("; haptic %1 triangles (%2, max deviation %3 mm%4)")
                  .arg(m.Haptic.Triangles)
                  .arg(Text(m.Haptic.Method))
                  .arg(m.Haptic.MaxDeviationMm, 0, 'f', 2)
                  .arg(m.Haptic.Manifold ? ", closed" : ", NOT closed");
    lines << line;
  }
  if (!errors.isEmpty()) {
    this->ShowError("Create models failed: " + errors.join("\n") + (lines.isEmpty() ? "" : "\n" + lines.join("\n")));
    return false;
  }
  this->ShowStatus(lines.join("\n"));
  return true;
}
