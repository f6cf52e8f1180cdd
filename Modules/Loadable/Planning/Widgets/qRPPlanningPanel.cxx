#include "qRPPlanningPanel.h"

#include <algorithm>
#include <cmath>

#include <QHeaderView>
#include <QTimer>

#include "qRPProfilePlot.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"

namespace {

QString Mm(double v) { return QString("%1 mm").arg(v, 0, 'f', 1); }

// Combo items: a node's name, its ID as data.
void FillCombo(QComboBox* combo, const std::vector<vtkRPNode*>& nodes, bool withNone) {
  const QString kept = combo->currentData().toString();
  combo->clear();
  if (withNone) combo->addItem("(none)", QString());
  for (vtkRPNode* node : nodes) combo->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  const int index = combo->findData(kept);
  combo->setCurrentIndex(index >= 0 ? index : (withNone && combo->count() > 1 ? 1 : 0));
}

}  // namespace

qRPPlanningPanel::qRPPlanningPanel(vtkRPPlanningLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  // What a .ui cannot say: the name column takes the tables' spare width.
  this->Structures->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
  this->Clearances->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
  this->ConnectWidgets();
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);  // display rate: the figures follow a dragged point
  connect(this->Timer, &QTimer::timeout, this, &qRPPlanningPanel::OnTimer);
  this->SceneWatch = std::make_unique<rp::SceneNodesWatch>(logic ? logic->GetScene() : nullptr);
  this->RefreshNodeLists();
  this->Timer->start();
}

qRPPlanningPanel::~qRPPlanningPanel() {
  this->Timer->stop();
}

void qRPPlanningPanel::ConnectWidgets() {
  connect(this->Volume, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) { this->ApplyPatient(); });
  connect(this->Segmentation, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) { this->ApplyPatient(); });
  connect(this->Structures, &QTableWidget::itemChanged, this, [this](QTableWidgetItem* item) {
    if (!this->Refreshing) this->ApplyStructureRow(item->row());
  });
  for (const auto& [button, className] : {std::pair<QPushButton*, const char*>{this->NewTrajectoryButton, "vtkRPTrajectoryNode"},
                                          {this->NewScrewButton, "vtkRPScrewNode"},
                                          {this->NewCutPlaneButton, "vtkRPCutPlaneNode"}})
    connect(button, &QPushButton::clicked, this, [this, className = className]() { this->NewPlan(className); });
  connect(this->Plan, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (this->Refreshing) return;
    this->ShowPlanSettings();
    this->UpdateFigures();
  });
  for (QDoubleSpinBox* spin : {this->Diameter, this->ScrewDiameter, this->ScrewLength, this->HeadDiameter, this->HeadLength})
    connect(spin, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double) {
      if (!this->Refreshing) this->ApplyPlanSettings();
    });
  connect(this->Tissue, &QComboBox::currentTextChanged, this, [this](const QString&) {
    if (!this->Refreshing) this->ApplyPlanSettings();
  });
  connect(this->ProposeButton, &QPushButton::clicked, this, [this]() { this->Propose(); });
  connect(this->UseBestEntryButton, &QPushButton::clicked, this, [this]() {
    auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(this->CurrentPlan());
    const rp::ProposalResult& r = this->LastProposalResult;
    if (!trajectory || r.Best.empty() || static_cast<size_t>(r.Best.front()) >= this->Logic->GetCandidates().size()) return;
    const rp::Vec3 e = this->Logic->GetCandidates()[static_cast<size_t>(r.Best.front())];
    const double entry[3] = {e.x, e.y, e.z};
    trajectory->SetNthControlPointPositionWorld(vtkRPTrajectoryNode::EntryIndex, entry);
  });
}

void qRPPlanningPanel::showEvent(QShowEvent* event) {
  this->RefreshNodeLists();
  QWidget::showEvent(event);
}

void qRPPlanningPanel::RefreshNodeLists() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (!scene) return;
  this->Refreshing = true;
  FillCombo(this->Volume, scene->GetNodesByClass("vtkRPScalarVolumeNode"), true);
  FillCombo(this->Segmentation, scene->GetNodesByClass("vtkRPSegmentationNode"), true);
  FillCombo(this->Plan, scene->GetNodesByClass("vtkRPPlanNode"), false);
  const QString region = this->Region->currentData().toString();
  this->Region->clear();
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode"))
    if (node->GetAttribute("RoboPlan.riskMap").empty())
      this->Region->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode"))
    for (const rp::Segment& s : vtkRPSegmentationNode::SafeDownCast(node)->GetSegments())
      this->Region->addItem(QString::fromStdString(node->GetName() + ": " + s.Name),
                            QString::fromStdString(node->GetID() + "#" + s.ID));
  if (this->Region->findData(region) >= 0) this->Region->setCurrentIndex(this->Region->findData(region));
  if (this->Tissue->count() == 0 && this->Logic)
    for (const std::string& t : this->Logic->GetMaterials().TissueNames()) this->Tissue->addItem(QString::fromStdString(t));
  this->RefreshStructures();
  this->Refreshing = false;
  this->ApplyPatient();
  this->ShowPlanSettings();
}

// One row per model and per segment: a check box for "at risk" and the margin.
void qRPPlanningPanel::RefreshStructures() {
  vtkRPScene* scene = this->Logic->GetScene();
  this->Structures->setRowCount(0);
  auto addRow = [this](const std::string& label, const std::string& key, const rp::StructureProtection& p) {
    const int row = this->Structures->rowCount();
    this->Structures->insertRow(row);
    auto* name = new QTableWidgetItem(QString::fromStdString(label));
    name->setFlags(Qt::ItemIsEnabled);
    name->setData(Qt::UserRole, QString::fromStdString(key));
    auto* flag = new QTableWidgetItem;
    flag->setFlags(Qt::ItemIsEnabled | Qt::ItemIsUserCheckable);
    flag->setCheckState(p.Protected ? Qt::Checked : Qt::Unchecked);
    auto* margin = new QTableWidgetItem(QString::number(p.SafetyMarginMm));
    this->Structures->setItem(row, 0, name);
    this->Structures->setItem(row, 1, flag);
    this->Structures->setItem(row, 2, margin);
  };
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode"))
    if (node->GetAttribute("RoboPlan.riskMap").empty())
      addRow(node->GetName(), node->GetID(), vtkRPModelNode::SafeDownCast(node)->GetProtection());
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode"))
    for (const rp::Segment& s : vtkRPSegmentationNode::SafeDownCast(node)->GetSegments())
      addRow(node->GetName() + ": " + s.Name, node->GetID() + "#" + s.ID, s.Protection);
}

// A row edited: the flag and margin go onto the model or segment (where they are stored).
void qRPPlanningPanel::ApplyStructureRow(int row) {
  vtkRPScene* scene = this->Logic->GetScene();
  const std::string key = this->Structures->item(row, 0)->data(Qt::UserRole).toString().toStdString();
  bool ok = false;
  const double margin = this->Structures->item(row, 2)->text().toDouble(&ok);
  const rp::StructureProtection protection{this->Structures->item(row, 1)->checkState() == Qt::Checked,
                                           ok && margin >= 0 ? margin : 0.0};
  const size_t hash = key.find('#');
  if (hash == std::string::npos) {
    if (auto* model = vtkRPModelNode::SafeDownCast(scene->GetNodeByID(key))) model->SetProtection(protection);
  } else if (auto* seg = vtkRPSegmentationNode::SafeDownCast(scene->GetNodeByID(key.substr(0, hash)))) {
    if (const rp::Segment* found = seg->GetSegmentByID(key.substr(hash + 1))) {
      rp::Segment segment = *found;
      segment.Protection = protection;
      seg->SetSegment(segment);
    }
  }
  this->UpdateFigures();
}

void qRPPlanningPanel::ApplyPatient() {
  if (this->Refreshing || !this->Logic || !this->Logic->GetScene()) return;
  vtkRPScene* scene = this->Logic->GetScene();
  auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodeByID(this->Volume->currentData().toString().toStdString()));
  auto* seg = vtkRPSegmentationNode::SafeDownCast(scene->GetNodeByID(this->Segmentation->currentData().toString().toStdString()));
  std::string error;
  if (!this->Logic->SetPatientData(ct, seg, error)) {
    this->Problem->setText(QString::fromStdString(error));
    this->Problem->show();
    return;
  }
  this->UpdateFigures();
}

vtkRPNode* qRPPlanningPanel::CurrentPlan() const {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  return scene ? scene->GetNodeByID(this->Plan->currentData().toString().toStdString()) : nullptr;
}

vtkRPNode* qRPPlanningPanel::NewPlan(const char* className) {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (!scene) return nullptr;
  vtkSmartPointer<vtkRPNode> node = scene->CreateNodeByClass(className);
  auto* plan = vtkRPPlanNode::SafeDownCast(node);
  if (!plan) return nullptr;
  const std::string base = std::string(className) == "vtkRPScrewNode" ? "Screw"
                           : std::string(className) == "vtkRPCutPlaneNode" ? "Cut" : "Trajectory";
  plan->SetName(scene->GenerateUniqueName(base));
  if (auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodeByID(this->Volume->currentData().toString().toStdString())))
    plan->SetPlannedOn(vtkRPPlanningLogic::VolumeIdentity(ct));
  if (auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(plan)) trajectory->SetToolDiameterMm(this->Diameter->value());
  scene->AddNode(plan);  // empty: the views place its points next
  this->RefreshNodeLists();
  this->Plan->setCurrentIndex(this->Plan->findData(QString::fromStdString(plan->GetID())));
  return plan;
}

void qRPPlanningPanel::ShowPlanSettings() {
  vtkRPNode* node = this->CurrentPlan();
  auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(node);
  auto* screw = vtkRPScrewNode::SafeDownCast(node);
  this->Refreshing = true;
  if (trajectory) {
    this->Diameter->setValue(trajectory->GetToolDiameterMm());
    this->Tissue->setCurrentText(QString::fromStdString(trajectory->GetIntendedTissue()));
  }
  if (screw) {
    this->ScrewDiameter->setValue(screw->GetScrewDiameterMm());
    this->ScrewLength->setValue(screw->GetScrewLengthMm());
    this->HeadDiameter->setValue(screw->GetHeadDiameterMm());
    this->HeadLength->setValue(screw->GetHeadLengthMm());
  }
  this->Diameter->setEnabled(trajectory != nullptr);
  this->Tissue->setEnabled(trajectory != nullptr);
  for (QDoubleSpinBox* spin : {this->ScrewDiameter, this->ScrewLength, this->HeadDiameter, this->HeadLength})
    spin->setEnabled(screw != nullptr);
  this->Refreshing = false;
}

void qRPPlanningPanel::ApplyPlanSettings() {
  vtkRPNode* node = this->CurrentPlan();
  if (auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(node)) {
    const int previous = trajectory->StartModify();
    trajectory->SetToolDiameterMm(this->Diameter->value());
    trajectory->SetIntendedTissue(this->Tissue->currentText().toStdString());
    if (auto* screw = vtkRPScrewNode::SafeDownCast(node)) {
      screw->SetScrewDiameterMm(this->ScrewDiameter->value());
      screw->SetScrewLengthMm(this->ScrewLength->value());
      screw->SetHeadDiameterMm(this->HeadDiameter->value());
      screw->SetHeadLengthMm(this->HeadLength->value());
    }
    trajectory->EndModify(previous);
  }
  this->UpdateFigures();
}

// What the figures depend on: the plan (and its transforms), the structures at risk.
unsigned long qRPPlanningPanel::WatchedTime() const {
  unsigned long time = 0;
  if (vtkRPNode* plan = this->CurrentPlan()) time = plan->GetMTime();
  if (vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr) {
    for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode"))
      if (node->GetAttribute("RoboPlan.riskMap").empty()) time = std::max<unsigned long>(time, node->GetMTime());
    for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode")) time = std::max<unsigned long>(time, node->GetMTime());
  }
  return time;
}

void qRPPlanningPanel::OnTimer() {
  if (this->SceneWatch->TakeChanged()) {
    this->RefreshNodeLists();
    return;
  }
  if (this->WatchedTime() != this->ShownTime) this->UpdateFigures();
}

void qRPPlanningPanel::UpdateFigures() {
  if (!this->Logic) return;
  this->ShownTime = this->WatchedTime();
  this->Problem->hide();
  vtkRPNode* node = this->CurrentPlan();
  if (auto* plane = vtkRPCutPlaneNode::SafeDownCast(node)) {
    (void)plane;
    this->ShowCut();
    return;
  }
  auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(node);
  if (!trajectory || !trajectory->IsComplete()) {
    this->Summary->setText(trajectory ? "click the entry, then the target, in the views" : "no plan: make one above");
    return;
  }
  if (auto* screw = vtkRPScrewNode::SafeDownCast(trajectory)) this->Logic->UpdateScrewModel(screw);
  rp::TrajectoryFigures figures;
  std::string error;
  ++this->FigureUpdates;
  if (!this->Logic->ComputeFigures(trajectory, figures, error)) {
    this->Problem->setText(QString::fromStdString(error));
    this->Problem->show();
    return;
  }
  this->ShowFigures(figures);
  if (this->FollowTarget->isChecked()) this->Propose();
}

void qRPPlanningPanel::ShowFigures(const rp::TrajectoryFigures& f) {
  this->LastFigures = f;
  QString text = QString("Length %1, in bone %2").arg(Mm(f.LengthMm), Mm(f.LengthInBoneMm));
  for (const rp::DepthInterval& b : f.Bone) text += QString(" [%1-%2]").arg(b.FromMm, 0, 'f', 1).arg(b.ToMm, 0, 'f', 1);
  for (const rp::TissueLength& t : f.Tissues) text += QString("\n  %1: %2").arg(QString::fromStdString(t.Name), Mm(t.LengthMm));
  if (f.CorticalSurfaceShare >= 0) text += QString("\nCortical share of the tool's surface: %1 %").arg(100 * f.CorticalSurfaceShare, 0, 'f', 0);
  this->Summary->setText(text);
  if (f.Breach.Found) {
    this->Breach->setText(QString("Breach %1 beyond the bone at %2 deep: Gertzbein-Robbins grade %3")
                              .arg(Mm(f.Breach.BreachMm), Mm(f.Breach.DepthMm))
                              .arg(f.Breach.Grade));
    this->Breach->setStyleSheet(f.Breach.Grade >= 2 ? "color: #c0392b; font-weight: bold" : "color: #b9770e");
  } else {
    this->Breach->setText("No breach: the tool stays in bone where its axis is");
    this->Breach->setStyleSheet("color: #1e8449");
  }
  this->Clearances->setRowCount(0);
  for (const rp::ClearanceFigure& c : f.Clearances) {
    const int row = this->Clearances->rowCount();
    this->Clearances->insertRow(row);
    const QColor colour = c.UnderMargin ? QColor(192, 57, 43) : QColor(30, 132, 73);
    const QString items[3] = {QString::fromStdString(c.Name), Mm(c.ClearanceMm), Mm(c.DepthMm)};
    for (int col = 0; col < 3; ++col) {
      auto* item = new QTableWidgetItem(items[col]);
      item->setForeground(colour);
      this->Clearances->setItem(row, col, item);
    }
  }
  this->ProfilePlot->SetProfile(f, this->Logic->GetInputs().Tissue().BoneRanges);
}

void qRPPlanningPanel::ShowCut() {
  std::vector<vtkRPPlanningLogic::BoneCut> cuts;
  std::string error;
  if (!this->Logic->ComputeCut(vtkRPCutPlaneNode::SafeDownCast(this->CurrentPlan()), cuts, error)) {
    this->Summary->setText(QString::fromStdString(error));
    return;
  }
  QString text;
  for (const auto& c : cuts)
    text += QString("%1: %2 cm³ on the normal's side, %3 cm³ on the other; cut %4 cm²\n")
                .arg(QString::fromStdString(c.Bone))
                .arg(c.Figures.PositiveVolumeMm3 / 1000, 0, 'f', 1)
                .arg(c.Figures.NegativeVolumeMm3 / 1000, 0, 'f', 1)
                .arg(c.Figures.CutAreaMm2 / 100, 0, 'f', 1);
  this->Summary->setText(text.trimmed());
  this->Breach->clear();
  this->Clearances->setRowCount(0);
}

bool qRPPlanningPanel::Propose() {
  auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(this->CurrentPlan());
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  double target[3], entry[3];
  if (!scene || !trajectory || !trajectory->GetTargetWorld(target)) {
    this->ProposalSummary->setText("place a trajectory's target first");
    return false;
  }
  vtkRPPlanningLogic::ProposalOptions options;
  options.ToolDiameterMm = trajectory->GetToolDiameterMm();
  options.SpacingMm = this->Spacing->value();
  options.StayInBone = this->StayInBone->isChecked();
  if (this->SphereRadius->value() > 0 && trajectory->GetEntryWorld(entry)) {
    std::copy(entry, entry + 3, options.SphereCenter);
    options.SphereRadiusMm = this->SphereRadius->value();
  }
  // The region's candidates are made once per region choice (dragging the target reuses them).
  const std::string region = this->Region->currentData().toString().toStdString() + "|" +
                             std::to_string(options.SpacingMm) + "|" + std::to_string(options.SphereRadiusMm);
  std::string error;
  bool ok = true;
  if (region != this->RegionShown) {
    const std::string id = this->Region->currentData().toString().toStdString();
    const size_t hash = id.find('#');
    ok = hash == std::string::npos
             ? this->Logic->SetEntryRegion(vtkRPModelNode::SafeDownCast(scene->GetNodeByID(id)), options, error)
             : this->Logic->SetEntryRegionFromSegment(vtkRPSegmentationNode::SafeDownCast(scene->GetNodeByID(id.substr(0, hash))),
                                                      id.substr(hash + 1), options, error);
    if (ok) this->RegionShown = region;
  }
  ok = ok && this->Logic->Propose(target, options, this->LastProposalResult, error);
  if (!ok) {
    this->ProposalSummary->setText(QString::fromStdString(error));
    return false;
  }
  this->Logic->UpdateRiskMap(this->LastProposalResult);
  const rp::ProposalResult& r = this->LastProposalResult;
  QString text = QString("%1 entries scored in %2 ms").arg(r.Scores.size()).arg(1000 * r.Seconds, 0, 'f', 1);
  for (size_t k = 0; k < r.Best.size(); ++k) {
    const rp::Vec3& p = this->Logic->GetCandidates()[static_cast<size_t>(r.Best[k])];
    text += QString("\n%1. %2, %3, %4: clearance %5").arg(k + 1).arg(p.x, 0, 'f', 1).arg(p.y, 0, 'f', 1).arg(p.z, 0, 'f', 1)
                .arg(Mm(r.Scores[static_cast<size_t>(r.Best[k])].ClearanceMm));
  }
  this->ProposalSummary->setText(text);
  return true;
}

QString qRPPlanningPanel::FiguresText() const { return this->Summary->text() + "\n" + this->Breach->text(); }
QString qRPPlanningPanel::ProblemText() const { return this->Problem->isHidden() ? QString() : this->Problem->text(); }
QString qRPPlanningPanel::ProposalText() const { return this->ProposalSummary->text(); }
