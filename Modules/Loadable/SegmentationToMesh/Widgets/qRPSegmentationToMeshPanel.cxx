#include "qRPSegmentationToMeshPanel.h"

#include <algorithm>
#include <array>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressDialog>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>

#include <vtkCommand.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpBoneSplit.h"
#include "rpLabelmapInput.h"
#include "rpLabelmapToMesh.h"
#include "rpMeshLevelOfDetail.h"
#include "rpMaterial.h"
#include "rpSegmentationToModels.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

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

}  // namespace

qRPSegmentationToMeshPanel::qRPSegmentationToMeshPanel(vtkRPScene* scene, QWidget* parent)
    : QWidget(parent), Scene(scene) {
  QLayout* inputForm = this->BuildInputForm();
  QWidget* methodBox = this->BuildMethodBox();
  QWidget* editBox = this->BuildEditBox();
  QWidget* meshBox = this->BuildSurfaceBox();
  this->StatusLabel = new QLabel;
  this->StatusLabel->setWordWrap(true);
  this->StatusLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);

  auto* layout = new QVBoxLayout(this);
  layout->addLayout(inputForm);
  layout->addWidget(methodBox);
  layout->addWidget(editBox);
  layout->addWidget(meshBox);
  layout->addWidget(this->StatusLabel);
  layout->addStretch(1);

  this->ConnectWidgets();

  if (this->Scene) {
    const unsigned long events[4] = {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeRemovedEvent,
                                     vtkRPScene::EndImportEvent, vtkRPScene::EndCloseEvent};
    for (int i = 0; i < 4; ++i)
      this->SceneObservers[i] = this->Scene->AddObserver(events[i], this, &qRPSegmentationToMeshPanel::OnSceneEvent);
  }
  this->OnPresetChanged();
  this->OnMethodChanged();
  this->RefreshNodeCombos();
}

QLayout* qRPSegmentationToMeshPanel::BuildInputForm() {
  // Input and target.
  this->VolumeCombo = new QComboBox;
  this->SegmentationCombo = new QComboBox;
  this->NewSegmentationButton = new QPushButton("New");
  auto* segmentationRow = new QHBoxLayout;
  segmentationRow->addWidget(this->SegmentationCombo, 1);
  segmentationRow->addWidget(this->NewSegmentationButton);
  this->LabelTableEdit = new QLineEdit;
  this->LabelTableEdit->setPlaceholderText("none: segments are named \"Label N\"");
  this->LabelTableEdit->setToolTip("Slicer colour table (.ctbl/.txt) or ITK-SNAP label description file");
  this->LabelTableBrowseButton = new QPushButton("...");
  this->LabelmapButton = new QPushButton("Input volume is a labelmap: one segment per label");
  auto* tableRow = new QHBoxLayout;
  tableRow->addWidget(this->LabelTableEdit, 1);
  tableRow->addWidget(this->LabelTableBrowseButton);
  auto* inputForm = new QFormLayout;
  inputForm->addRow("Input volume", this->VolumeCombo);
  inputForm->addRow("Segmentation", segmentationRow);
  inputForm->addRow("Label table", tableRow);
  inputForm->addRow(this->LabelmapButton);

  return inputForm;
}

QWidget* qRPSegmentationToMeshPanel::BuildMethodBox() {
  // Segmentation method.
  this->MethodCombo = new QComboBox;
  this->MethodCombo->addItems({"Threshold preset", "Manual thresholds", "Region growing", "Confidence connected"});
  this->PresetCombo = new QComboBox;
  for (const auto& preset : rp::ThresholdPresets()) this->PresetCombo->addItem(QString::fromStdString(preset.Name));
  this->LowerSpin = new QDoubleSpinBox;
  this->UpperSpin = new QDoubleSpinBox;
  for (QDoubleSpinBox* spin : {this->LowerSpin, this->UpperSpin}) {
    spin->setRange(-32768, 65535);
    spin->setDecimals(1);
    spin->setSuffix(" HU");
  }
  this->SeedsCombo = new QComboBox;
  this->MultiplierSpin = new QDoubleSpinBox;
  this->MultiplierSpin->setRange(0.1, 10);
  this->MultiplierSpin->setValue(2.5);
  this->IterationsSpin = new QSpinBox;
  this->IterationsSpin->setRange(0, 20);
  this->IterationsSpin->setValue(3);
  this->SegmentNameEdit = new QLineEdit;
  this->TissueCombo = new QComboBox;
  this->TissueCombo->setEditable(true);
  // Tissue classes are the material table's (Resources/Materials/materials.json), so every class
  // offered here has haptic properties.
  rp::MaterialTable materials;
  std::string materialsError;
  if (rp::LoadMaterialTable(materials, materialsError))
    for (const std::string& tissue : materials.TissueNames()) this->TissueCombo->addItem(QString::fromStdString(tissue));
  else
    this->TissueCombo->setToolTip(QString::fromStdString(materialsError));
  this->ApplyButton = new QPushButton("Apply");
  this->SplitBonesButton = new QPushButton("Bones one by one");
  this->SplitBonesButton->setToolTip(
      "One segment per bone of the CT: touching bones split, table and specks dropped, knee bones named; "
      "the seed list's points name bones (by their labels) or force a split");
  auto* methodForm = new QFormLayout;
  methodForm->addRow("Method", this->MethodCombo);
  methodForm->addRow("Preset", this->PresetCombo);
  methodForm->addRow("Lower", this->LowerSpin);
  methodForm->addRow("Upper", this->UpperSpin);
  methodForm->addRow("Seeds", this->SeedsCombo);
  methodForm->addRow("Multiplier (k·σ)", this->MultiplierSpin);
  methodForm->addRow("Iterations", this->IterationsSpin);
  methodForm->addRow("Segment name", this->SegmentNameEdit);
  methodForm->addRow("Tissue class", this->TissueCombo);
  auto* applyRow = new QHBoxLayout;
  applyRow->addWidget(this->ApplyButton);
  applyRow->addWidget(this->SplitBonesButton);
  methodForm->addRow(applyRow);
  auto* methodBox = new QGroupBox("Segment");
  methodBox->setLayout(methodForm);
  return methodBox;
}

QWidget* qRPSegmentationToMeshPanel::BuildEditBox() {
  // Editing of the current segment.
  this->SegmentCombo = new QComboBox;
  this->MorphologyRadiusSpin = new QDoubleSpinBox;
  this->MorphologyRadiusSpin->setRange(0.1, 50);
  this->MorphologyRadiusSpin->setValue(1.0);
  this->MorphologyRadiusSpin->setSuffix(" mm");
  this->ClosingButton = new QPushButton("Closing");
  this->OpeningButton = new QPushButton("Opening");
  this->FillHolesButton = new QPushButton("Fill holes");
  this->KeepLargestButton = new QPushButton("Keep largest");
  auto* editButtons = new QGridLayout;
  editButtons->addWidget(this->ClosingButton, 0, 0);
  editButtons->addWidget(this->OpeningButton, 0, 1);
  editButtons->addWidget(this->FillHolesButton, 1, 0);
  editButtons->addWidget(this->KeepLargestButton, 1, 1);
  auto* editForm = new QFormLayout;
  editForm->addRow("Current segment", this->SegmentCombo);
  editForm->addRow("Radius", this->MorphologyRadiusSpin);
  editForm->addRow(editButtons);
  auto* editBox = new QGroupBox("Edit");
  editBox->setLayout(editForm);
  return editBox;
}

QWidget* qRPSegmentationToMeshPanel::BuildSurfaceBox() {
  // Surface.
  this->MeshMethodCombo = new QComboBox;
  this->MeshMethodCombo->addItems({"Gaussian (volume-corrected)", "Windowed sinc (volume-corrected)",
                                   "Slicer default", "Discrete (no smoothing)"});
  this->SigmaSpin = new QDoubleSpinBox;
  this->SigmaSpin->setRange(0, 5);
  this->SigmaSpin->setSingleStep(0.1);
  this->SigmaSpin->setValue(1.0);
  this->SigmaSpin->setSuffix(" voxels");
  this->GridStepSpin = new QDoubleSpinBox;
  this->GridStepSpin->setRange(1, 8);
  this->GridStepSpin->setSingleStep(0.5);
  this->GridStepSpin->setValue(1.0);
  this->GridStepSpin->setSuffix(" voxels");
  this->DisplayTrianglesSpin = new QSpinBox;
  this->DisplayTrianglesSpin->setRange(0, 10000000);
  this->DisplayTrianglesSpin->setSpecialValueText("no target");
  this->DisplayTrianglesSpin->setSingleStep(10000);
  this->HapticTrianglesSpin = new QSpinBox;
  this->HapticTrianglesSpin->setRange(0, 10000000);
  this->HapticTrianglesSpin->setSpecialValueText("no haptic mesh");
  this->HapticTrianglesSpin->setSingleStep(5000);
  this->HapticTrianglesSpin->setValue(20000);
  this->AllSegmentsCheck = new QCheckBox("All segments");
  this->PreviewButton = new QPushButton("Preview");
  this->CreateModelsButton = new QPushButton("Create models");
  auto* meshButtons = new QHBoxLayout;
  meshButtons->addWidget(this->PreviewButton);
  meshButtons->addWidget(this->CreateModelsButton);
  auto* meshForm = new QFormLayout;
  meshForm->addRow("Method", this->MeshMethodCombo);
  meshForm->addRow("Smoothing σ", this->SigmaSpin);
  meshForm->addRow("Grid step", this->GridStepSpin);
  meshForm->addRow("Display triangles", this->DisplayTrianglesSpin);
  meshForm->addRow("Haptic triangles", this->HapticTrianglesSpin);
  meshForm->addRow(this->AllSegmentsCheck);
  meshForm->addRow(meshButtons);
  auto* meshBox = new QGroupBox("Surface");
  meshBox->setLayout(meshForm);
  return meshBox;
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
  if (!this->Scene) return;
  for (unsigned long tag : this->SceneObservers)
    if (tag) this->Scene->RemoveObserver(tag);
  this->RemovePreview();  // temporary: never outlives the panel
}

void qRPSegmentationToMeshPanel::OnSceneEvent(vtkObject*, unsigned long event, void* callData) {
  if (this->Scene->IsImporting() && event == vtkRPScene::NodeAddedEvent) return;  // EndImportEvent refreshes
  if (event == vtkRPScene::NodeAddedEvent || event == vtkRPScene::NodeRemovedEvent) {
    auto* node = static_cast<vtkRPNode*>(callData);
    if (node && event == vtkRPScene::NodeRemovedEvent && node->GetID() == this->PreviewID) this->PreviewID.clear();
    if (node && !node->IsA("vtkRPScalarVolumeNode") && !node->IsA("vtkRPSegmentationNode") &&
        !node->IsA("vtkRPFiducialListNode"))
      return;  // models (ours included) do not change the combos
  }
  this->RefreshNodeCombos();
}

void qRPSegmentationToMeshPanel::RefreshNodeCombos() {
  if (!this->Scene) return;
  FillNodeCombo(this->VolumeCombo, this->Scene->GetNodesByClass("vtkRPScalarVolumeNode"), QString());
  FillNodeCombo(this->SegmentationCombo, this->Scene->GetNodesByClass("vtkRPSegmentationNode"), QString());
  FillNodeCombo(this->SeedsCombo, this->Scene->GetNodesByClass("vtkRPFiducialListNode"), "(no seeds)");
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
  const QString keep = select.empty() ? this->SegmentCombo->currentData().toString() : QString::fromStdString(select);
  const QSignalBlocker block(this->SegmentCombo);
  this->SegmentCombo->clear();
  if (vtkRPSegmentationNode* segmentation = this->CurrentSegmentation())
    for (const auto& s : segmentation->GetSegments())
      this->SegmentCombo->addItem(QString::fromStdString(s.Name.empty() ? s.ID : s.Name), QString::fromStdString(s.ID));
  const int index = this->SegmentCombo->findData(keep);
  this->SegmentCombo->setCurrentIndex(index >= 0 ? index : (this->SegmentCombo->count() > 0 ? 0 : -1));
}

void qRPSegmentationToMeshPanel::OnPresetChanged() {
  const rp::ThresholdPreset* preset = rp::FindThresholdPreset(this->PresetCombo->currentText().toStdString());
  if (!preset) return;
  this->LowerSpin->setValue(preset->Lower);
  this->UpperSpin->setValue(preset->Upper);
  this->SegmentNameEdit->setText(QString::fromStdString(preset->Name));
  this->TissueCombo->setCurrentText(QString::fromStdString(preset->TissueClass));
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
  if (!this->Scene) return nullptr;
  return vtkRPScalarVolumeNode::SafeDownCast(
      this->Scene->GetNodeByID(this->VolumeCombo->currentData().toString().toStdString()));
}

vtkRPSegmentationNode* qRPSegmentationToMeshPanel::CurrentSegmentation() const {
  if (!this->Scene) return nullptr;
  return vtkRPSegmentationNode::SafeDownCast(
      this->Scene->GetNodeByID(this->SegmentationCombo->currentData().toString().toStdString()));
}

std::string qRPSegmentationToMeshPanel::CurrentSegmentID() const {
  return this->SegmentCombo->currentData().toString().toStdString();
}

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
  if (!this->Scene) return nullptr;
  vtkNew<vtkRPSegmentationNode> segmentation;
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  segmentation->SetName(volume ? volume->GetName() + " segmentation" : std::string("Segmentation"));
  this->Scene->AddNode(segmentation);  // the observer refreshes the combo
  const int index = this->SegmentationCombo->findData(QString::fromStdString(segmentation->GetID()));
  this->SegmentationCombo->setCurrentIndex(index);
  this->RefreshSegments();
  return segmentation;
}

bool qRPSegmentationToMeshPanel::SplitBones() {
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  if (!volume || !volume->GetImageData()) {
    this->ShowError("Bones one by one: pick an input volume (a CT)");
    return false;
  }
  rp::BoneSplitOptions options;
  if (auto* list = vtkRPFiducialListNode::SafeDownCast(
          this->Scene->GetNodeByID(this->SeedsCombo->currentData().toString().toStdString()))) {
    for (int i = 0; i < list->GetNumberOfControlPoints(); ++i) {
      rp::BoneSeed seed;
      list->GetNthControlPointPositionWorld(i, seed.RAS.data());
      // Only labels a user gave name bones (not the generated "<list>-<n>").
      const std::string& label = list->GetNthControlPoint(i).Label;
      seed.Name = list->IsGeneratedLabel(label) ? "" : label;
      options.Seeds.push_back(seed);
    }
  }
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName(volume->GetName() + " bones");
  rp::BoneSplitResult result;
  std::string error;
  bool ok = false;
  {
    ProgressScope progress(this, "Bones one by one");
    ok = rp::SplitBones(volume, segmentation, options, result, error, progress.Callback());
  }
  if (!ok) {
    this->ShowError("Bones one by one failed: " + QString::fromStdString(error));
    return false;
  }
  this->Scene->AddNode(segmentation);
  this->SegmentationCombo->setCurrentIndex(
      this->SegmentationCombo->findData(QString::fromStdString(segmentation->GetID())));
  this->RefreshSegments();
  QStringList lines;
  for (const auto& b : result.Bones)
    lines << QString("%1: %2 ml%3")
                 .arg(QString::fromStdString(b.ID))
                 .arg(b.VolumeMl, 0, 'f', 1)
                 .arg(b.NamedBy.empty() ? QString() : " (named by " + QString::fromStdString(b.NamedBy) + ")");
  lines << QString("%1 touching pair(s) split; dropped %2 speck(s), %3 piece(s) outside the body")
               .arg(result.Splits)
               .arg(result.DroppedSpecks)
               .arg(result.DroppedOutsideBody);
  for (const auto& note : result.Notes) lines << QString::fromStdString(note);
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
    this->ShowError("Labelmap: " + QString::fromStdString(error));
    return false;
  }
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName(volume->GetName() + " segments");
  bool ok = false;
  {
    BusyScope busy(this);
    vtkNew<vtkImageData> copy;  // the segmentation is edited; the volume stays as loaded
    copy->DeepCopy(volume->GetImageData());
    ok = rp::LabelmapToSegmentation(copy, volume->GetIJKToRASMatrix(), tablePath.empty() ? nullptr : &table,
                                    segmentation, error);
  }
  if (!ok) {
    this->ShowError("Labelmap: '" + QString::fromStdString(volume->GetName()) + "': " + QString::fromStdString(error));
    return false;
  }
  this->Scene->AddNode(segmentation);
  this->SegmentationCombo->setCurrentIndex(
      this->SegmentationCombo->findData(QString::fromStdString(segmentation->GetID())));
  this->RefreshSegments();
  QStringList names;
  for (const auto& s : segmentation->GetSegments()) names << QString::fromStdString(s.Name);
  this->ShowStatus(QString("%1 segment(s) from the labelmap '%2': %3")
                       .arg(segmentation->GetNumberOfSegments())
                       .arg(QString::fromStdString(volume->GetName()))
                       .arg(names.join(", ")));
  return true;
}

rp::SegmentTarget qRPSegmentationToMeshPanel::Target() const {
  rp::SegmentTarget target;
  target.Name = this->SegmentNameEdit->text().trimmed().toStdString();
  target.ID = target.Name;
  target.TissueClass = this->TissueCombo->currentText().trimmed().toStdString();
  if (const rp::ThresholdPreset* preset = rp::FindThresholdPreset(this->PresetCombo->currentText().toStdString()))
    target.Color = preset->Color;
  if (vtkRPSegmentationNode* segmentation = this->CurrentSegmentation())
    if (const auto* existing = segmentation->GetSegmentByID(target.ID))
      target.Color = {existing->Color[0], existing->Color[1], existing->Color[2]};  // keep the user's colour
  return target;
}

bool qRPSegmentationToMeshPanel::Apply() {
  vtkRPScalarVolumeNode* volume = this->CurrentVolume();
  if (!volume) {
    this->ShowError("Apply: pick an input volume");
    return false;
  }
  const rp::SegmentTarget target = this->Target();
  if (target.ID.empty()) {
    this->ShowError("Apply: give the segment a name");
    return false;
  }
  const int method = this->MethodCombo->currentIndex();
  std::vector<std::array<double, 3>> seeds;
  if (method == RegionGrowing || method == ConfidenceConnected) {
    auto* list = vtkRPFiducialListNode::SafeDownCast(
        this->Scene->GetNodeByID(this->SeedsCombo->currentData().toString().toStdString()));
    for (int i = 0; list && i < list->GetNumberOfControlPoints(); ++i) {
      std::array<double, 3> p{};
      list->GetNthControlPointPositionWorld(i, p.data());
      seeds.push_back(p);
    }
    if (seeds.empty()) {
      this->ShowError("Apply: " + this->MethodCombo->currentText() +
                      " needs seeds: pick a fiducial list with at least one point");
      return false;
    }
  }
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  if (!segmentation) segmentation = this->NewSegmentation();
  rp::EditResult result;
  std::string error;
  bool ok = false;
  {
    BusyScope busy(this);
    switch (method) {
      case PresetThreshold: {
        const rp::ThresholdPreset* preset = rp::FindThresholdPreset(this->PresetCombo->currentText().toStdString());
        ok = preset && rp::SegmentationEditor::Threshold(volume, segmentation, target, preset->Lower, preset->Upper,
                                                         result, error);
        break;
      }
      case ManualThreshold:
        ok = rp::SegmentationEditor::Threshold(volume, segmentation, target, this->LowerSpin->value(),
                                               this->UpperSpin->value(), result, error);
        break;
      case RegionGrowing:
        ok = rp::SegmentationEditor::RegionGrow(volume, segmentation, target, seeds, this->LowerSpin->value(),
                                                this->UpperSpin->value(), result, error);
        break;
      default:
        ok = rp::SegmentationEditor::ConfidenceConnected(volume, segmentation, target, seeds,
                                                         this->MultiplierSpin->value(), this->IterationsSpin->value(),
                                                         2, result, error);
        break;
    }
  }
  if (!ok) {
    this->ShowError(QString("Apply failed: ") + QString::fromStdString(error));
    return false;
  }
  this->RefreshSegments(target.ID);
  this->ShowStatus(QString("%1: %2 voxels (%3 % of the volume)")
                       .arg(QString::fromStdString(target.Name))
                       .arg(result.Voxels)
                       .arg(100.0 * result.Fraction, 0, 'f', 2));
  return true;
}

bool qRPSegmentationToMeshPanel::ApplyMorphology(rp::Morphology op) {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  const std::string id = this->CurrentSegmentID();
  if (!segmentation || id.empty()) {
    this->ShowError("Morphology: no segment selected (Apply a segmentation first)");
    return false;
  }
  rp::EditResult result;
  std::string error;
  bool ok = false;
  {
    BusyScope busy(this);
    ok = rp::SegmentationEditor::ApplyMorphology(segmentation, id, op, this->MorphologyRadiusSpin->value(), result,
                                                 error);
  }
  if (!ok) {
    this->ShowError(QString("Morphology failed: ") + QString::fromStdString(error));
    return false;
  }
  this->ShowStatus(QString("%1: %2 voxels").arg(QString::fromStdString(id)).arg(result.Voxels));
  return true;
}

bool qRPSegmentationToMeshPanel::KeepLargest() {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  const std::string id = this->CurrentSegmentID();
  if (!segmentation || id.empty()) {
    this->ShowError("Keep largest: no segment selected (Apply a segmentation first)");
    return false;
  }
  rp::EditResult result;
  std::string error;
  bool ok = false;
  {
    BusyScope busy(this);
    ok = rp::SegmentationEditor::KeepLargestComponent(segmentation, id, result, error);
  }
  if (!ok) {
    this->ShowError(QString("Keep largest failed: ") + QString::fromStdString(error));
    return false;
  }
  this->ShowStatus(QString("%1: kept the largest of %2 components, %3 voxels")
                       .arg(QString::fromStdString(id))
                       .arg(result.Components)
                       .arg(result.Voxels));
  return true;
}

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

void qRPSegmentationToMeshPanel::RemovePreview() {
  if (this->PreviewID.empty() || !this->Scene) return;
  vtkRPNode* node = this->Scene->GetNodeByID(this->PreviewID);
  this->PreviewID.clear();
  if (node) this->Scene->RemoveNode(node);
}

bool qRPSegmentationToMeshPanel::Preview() {
  vtkRPSegmentationNode* segmentation = this->CurrentSegmentation();
  const std::string id = this->CurrentSegmentID();
  const auto* segment = segmentation ? segmentation->GetSegmentByID(id) : nullptr;
  if (!segment) {
    this->ShowError("Preview: no segment selected (Apply a segmentation first)");
    return false;
  }
  const rp::ModelBuildOptions options = this->BuildOptions();
  vtkNew<vtkPolyData> mesh;
  rp::MeshStats stats;
  std::string error;
  bool ok = false;
  {
    ProgressScope progress(this, "Meshing " + QString::fromStdString(id));
    ok = rp::LabelmapToMeshLOD(segmentation->GetImageData(), segmentation->GetIJKToRASMatrix(), segment->LabelValue,
                               options.Display, options.DisplayLOD, mesh, stats, error, progress.Callback());
  }
  const std::string name = (segment->Name.empty() ? segment->ID : segment->Name);
  if (!ok) {
    this->ShowError(QString("Preview failed: ") + QString::fromStdString(error));
    return false;
  }
  // Replace the previous preview (whatever segment it showed) rather than piling up models.
  auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->PreviewID));
  vtkSmartPointer<vtkRPModelNode> created;
  if (!model) {
    created = vtkSmartPointer<vtkRPModelNode>::New();
    model = created;
  }
  const int previous = model->StartModify();
  model->SetName(name + " (preview)");
  model->SetPolyData(mesh);
  model->SetColor(segment->Color[0], segment->Color[1], segment->Color[2]);
  model->SetHaptic(false);  // no tissue class either: haptics never touch a preview
  model->SetVisibility(true);
  model->EndModify(previous);
  if (created) {
    this->Scene->AddNode(created);
    this->PreviewID = created->GetID();
  }
  this->ShowStatus("Preview " + StatsText(QString::fromStdString(name), stats));
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
    models = rp::BuildSegmentModels(segmentation, options, nullptr, progress.Callback());  // added below
  }
  // Built first, then swapped in: a failure keeps the previous models of that segment.
  QStringList lines, errors;
  this->Scene->StartBatchProcess();
  for (const auto& m : models) {
    if (!m.Ok) {
      errors << QString::fromStdString(m.Error);
      continue;
    }
    for (const std::string& oldID : this->CreatedModelIDs[m.SegmentID])
      if (vtkRPNode* old = this->Scene->GetNodeByID(oldID)) this->Scene->RemoveNode(old);
    auto& ids = this->CreatedModelIDs[m.SegmentID];
    ids.clear();
    for (vtkRPModelNode* model : {m.DisplayModel.Get(), m.HapticModel.Get()}) {
      if (!model) continue;
      this->Scene->AddNode(model);
      ids.push_back(model->GetID());
    }
    QString line = StatsText(QString::fromStdString(m.Name), m.Display);
    if (m.HapticModel)
      line += QString("; haptic %1 triangles (%2, max deviation %3 mm%4)")
                  .arg(m.Haptic.Triangles)
                  .arg(QString::fromStdString(m.Haptic.Method))
                  .arg(m.Haptic.MaxDeviationMm, 0, 'f', 2)
                  .arg(m.Haptic.Manifold ? ", closed" : ", NOT closed");
    lines << line;
  }
  if (!lines.isEmpty()) this->RemovePreview();
  this->Scene->EndBatchProcess();
  if (!errors.isEmpty()) {
    this->ShowError("Create models failed: " + errors.join("\n") + (lines.isEmpty() ? "" : "\n" + lines.join("\n")));
    return false;
  }
  this->ShowStatus(lines.join("\n"));
  return true;
}
