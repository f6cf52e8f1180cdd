#include "qRPLandmarkRegistrationPanel.h"

#include <QHeaderView>
#include <QSignalBlocker>

#include <cmath>
#include <vector>

#include <vtkCommand.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpTransformNames.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPSliceNode.h"
#include "vtkRPTrackedToolNode.h"

namespace {
QString Mm(double value, int decimals = 3) {
  return std::isfinite(value) ? QString::number(value, 'f', decimals) : QString("–");
}

QString Point(const double p[3]) {
  return QString("%1, %2, %3").arg(p[0], 0, 'f', 1).arg(p[1], 0, 'f', 1).arg(p[2], 0, 'f', 1);
}

/// Green within half the threshold, orange up to it, red above (no threshold: green).
QColor ResidualColor(double residual, double threshold) {
  if (!std::isfinite(residual)) return QColor(200, 200, 200);
  if (threshold <= 0 || residual <= 0.5 * threshold) return QColor(150, 220, 150);
  if (residual <= threshold) return QColor(250, 200, 110);
  return QColor(240, 120, 120);
}

/// The top of a node's chain of parent transforms (the node itself when it has no parent).
vtkRPTransformableNode* RootOf(vtkRPTransformableNode* node) {
  while (vtkRPLinearTransformNode* parent = node->GetParentTransformNode()) node = parent;
  return node;
}

void SelectByID(QComboBox* combo, const QString& id) {
  const int index = combo->findData(id);
  combo->setCurrentIndex(index >= 0 ? index : 0);
}
}  // namespace

qRPLandmarkRegistrationPanel::qRPLandmarkRegistrationPanel(vtkRPLandmarkRegistrationLogic* logic, vtkRPScene* scene,
                                                           QWidget* parent)
    : QWidget(parent), Logic(logic), Scene(scene) {
  this->setupUi(this);
  this->Target[0] = this->TargetRSpin;
  this->Target[1] = this->TargetASpin;
  this->Target[2] = this->TargetSSpin;
  this->Table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);  // not a .ui property

  // ---- initial values from the logic
  if (this->Logic) {
    this->Mode->setCurrentIndex(this->Logic->GetMode() == rp::RegistrationMode::Similarity ? 1 : 0);
    this->Threshold->setValue(std::max(0.0, this->Logic->GetFREThreshold()));
    this->Fle->setValue(std::max(0.0, this->Logic->GetFLE()));
    this->AutoUpdate->setChecked(this->Logic->GetAutoUpdate());
    this->LogicTag = this->Logic->AddObserver(vtkCommand::ModifiedEvent, this,
                                              &qRPLandmarkRegistrationPanel::OnLogicOrListModified);
  }
  if (this->Scene) {
    const unsigned long events[4] = {vtkRPScene::NodeAddedEvent, vtkRPScene::NodeRemovedEvent,
                                      vtkRPScene::EndImportEvent, vtkRPScene::EndCloseEvent};
    for (int i = 0; i < 4; ++i)
      this->SceneTags[i] = this->Scene->AddObserver(events[i], this, &qRPLandmarkRegistrationPanel::OnSceneChanged);
  }
  this->UpdateNodeCombos();
  this->UpdateResults();

  for (QComboBox* combo : {this->FromCombo, this->ToCombo, this->OutputCombo})
    connect(combo, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { this->OnInputsChanged(); });
  connect(this->Mode, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { this->OnSettingsChanged(); });
  for (QDoubleSpinBox* box : {this->Threshold, this->Fle})
    connect(box, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this] { this->OnSettingsChanged(); });
  connect(this->AutoUpdate, &QCheckBox::toggled, this, [this] { this->OnSettingsChanged(); });
  connect(this->UseTarget, &QCheckBox::toggled, this, [this] { this->OnTargetChanged(); });
  for (QDoubleSpinBox* box : this->Target)
    connect(box, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this] { this->OnTargetChanged(); });
  connect(this->TargetListCombo, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
          [this] { this->OnTargetChanged(); });
  connect(this->TargetFromRowButton, &QPushButton::clicked, this, [this] { this->OnTargetFromSelectedRow(); });
  connect(this->NewOutputButton, &QPushButton::clicked, this, [this] { this->CreateOutputTransform(); });
  connect(this->CollectPointButton, &QPushButton::clicked, this, [this] { this->CollectPoint(); });
  connect(this->RemovePointButton, &QPushButton::clicked, this, [this] { this->OnRemoveSelectedPoint(); });
  connect(this->RegisterPushButton, &QPushButton::clicked, this, [this] { this->Register(); });
  connect(this->ApplyToolsButton, &QPushButton::clicked, this, [this] { this->ApplyToTools(); });
  connect(this->Table, &QTableWidget::currentCellChanged, this, [this](int row, int, int previousRow, int) {
    if (row >= 0 && row != previousRow && this->JumpSlices->isChecked()) this->JumpSlicesToSelectedPoint();
  });
}

qRPLandmarkRegistrationPanel::~qRPLandmarkRegistrationPanel() {
  if (this->ObservedFrom) this->ObservedFrom->RemoveObserver(this->FromTag);
  if (this->ObservedTo) this->ObservedTo->RemoveObserver(this->ToTag);
  if (this->ObservedTargetList) this->ObservedTargetList->RemoveObserver(this->TargetListTag);
  if (this->Logic) this->Logic->RemoveObserver(this->LogicTag);
  if (this->Scene) {
    for (unsigned long tag : this->SceneTags) this->Scene->RemoveObserver(tag);
  }
}

// ---------------------------------------------------------------- node selection

vtkRPFiducialListNode* qRPLandmarkRegistrationPanel::FromList() const {
  return this->Scene ? vtkRPFiducialListNode::SafeDownCast(
                           this->Scene->GetNodeByID(this->FromCombo->currentData().toString().toStdString()))
                     : nullptr;
}

vtkRPFiducialListNode* qRPLandmarkRegistrationPanel::ToList() const {
  return this->Scene ? vtkRPFiducialListNode::SafeDownCast(
                           this->Scene->GetNodeByID(this->ToCombo->currentData().toString().toStdString()))
                     : nullptr;
}

vtkRPLinearTransformNode* qRPLandmarkRegistrationPanel::OutputTransform() const {
  return this->Scene ? vtkRPLinearTransformNode::SafeDownCast(
                           this->Scene->GetNodeByID(this->OutputCombo->currentData().toString().toStdString()))
                     : nullptr;
}

vtkRPLinearTransformNode* qRPLandmarkRegistrationPanel::ToolTransform() const {
  return this->Scene ? vtkRPLinearTransformNode::SafeDownCast(
                           this->Scene->GetNodeByID(this->ToolCombo->currentData().toString().toStdString()))
                     : nullptr;
}

void qRPLandmarkRegistrationPanel::UpdateNodeCombos() {
  if (!this->Scene) return;
  const bool wasUpdating = this->UpdatingWidgets;
  this->UpdatingWidgets = true;
  auto fill = [this](QComboBox* combo, const char* className, const std::string& preferredID) {
    QString current = combo->currentData().toString();
    if (current.isEmpty() && !preferredID.empty()) current = QString::fromStdString(preferredID);
    const QSignalBlocker block(combo);
    combo->clear();
    combo->addItem("(none)", QString());
    for (vtkRPNode* node : this->Scene->GetNodesByClass(className))
      combo->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
    SelectByID(combo, current);
  };
  auto id = [](vtkRPNode* node) { return node ? node->GetID() : std::string(); };
  fill(this->FromCombo, "vtkRPFiducialListNode", this->Logic ? id(this->Logic->GetFromFiducials()) : "");
  fill(this->ToCombo, "vtkRPFiducialListNode", this->Logic ? id(this->Logic->GetToFiducials()) : "");
  fill(this->OutputCombo, "vtkRPLinearTransformNode", this->Logic ? id(this->Logic->GetOutputTransform()) : "");
  std::string tip;
  if (vtkRPNode* node = this->Scene->GetFirstNodeByName("StylusTipToStylus")) tip = node->GetID();
  fill(this->ToolCombo, "vtkRPLinearTransformNode", tip);
  fill(this->TargetListCombo, "vtkRPFiducialListNode", "");
  this->UpdatingWidgets = wasUpdating;
  this->OnInputsChanged();
}

namespace {
bool SelectByName(QComboBox* combo, const QString& name) {
  const int index = combo->findText(name);
  if (index < 0) return false;
  combo->setCurrentIndex(index);
  return true;
}
}  // namespace

bool qRPLandmarkRegistrationPanel::SelectFromList(const QString& name) { return SelectByName(this->FromCombo, name); }
bool qRPLandmarkRegistrationPanel::SelectToList(const QString& name) { return SelectByName(this->ToCombo, name); }
bool qRPLandmarkRegistrationPanel::SelectOutputTransform(const QString& name) {
  return SelectByName(this->OutputCombo, name);
}
bool qRPLandmarkRegistrationPanel::SelectToolTransform(const QString& name) {
  return SelectByName(this->ToolCombo, name);
}
bool qRPLandmarkRegistrationPanel::SelectTargetList(const QString& name) {
  return SelectByName(this->TargetListCombo, name);
}

vtkRPLinearTransformNode* qRPLandmarkRegistrationPanel::CreateOutputTransform(const QString& name) {
  if (!this->Scene) return nullptr;
  vtkNew<vtkRPLinearTransformNode> node;
  node->SetName(this->Scene->GenerateUniqueName(name.toStdString()));
  this->Scene->AddNode(node);  // NodeAddedEvent refills the combos
  SelectByID(this->OutputCombo, QString::fromStdString(node->GetID()));
  return node;
}

void qRPLandmarkRegistrationPanel::ObserveLists() {
  vtkRPFiducialListNode* from = this->FromList();
  vtkRPFiducialListNode* to = this->ToList();
  if (this->ObservedFrom != from) {
    if (this->ObservedFrom) this->ObservedFrom->RemoveObserver(this->FromTag);
    this->ObservedFrom = from;
    this->FromTag = from ? from->AddObserver(vtkCommand::ModifiedEvent, this,
                                             &qRPLandmarkRegistrationPanel::OnLogicOrListModified)
                         : 0;
  }
  if (this->ObservedTo != to) {
    if (this->ObservedTo) this->ObservedTo->RemoveObserver(this->ToTag);
    this->ObservedTo = to;
    this->ToTag = to ? to->AddObserver(vtkCommand::ModifiedEvent, this,
                                       &qRPLandmarkRegistrationPanel::OnLogicOrListModified)
                     : 0;
  }
}

void qRPLandmarkRegistrationPanel::OnInputsChanged() {
  if (this->UpdatingWidgets || !this->Logic) return;
  this->UpdatingWidgets = true;
  this->ObserveLists();
  this->Logic->SetFromFiducials(this->FromList());
  this->Logic->SetToFiducials(this->ToList());
  this->Logic->SetOutputTransform(this->OutputTransform());
  this->UpdatingWidgets = false;
  this->UpdateResults();
}

void qRPLandmarkRegistrationPanel::OnSettingsChanged() {
  if (this->UpdatingWidgets || !this->Logic) return;
  this->UpdatingWidgets = true;
  this->Logic->SetAutoUpdate(this->AutoUpdate->isChecked());
  this->Logic->SetMode(this->Mode->currentIndex() == 1 ? rp::RegistrationMode::Similarity
                                                       : rp::RegistrationMode::Rigid);
  this->Logic->SetFREThreshold(this->Threshold->value());
  this->Logic->SetFLE(this->Fle->value());
  this->UpdatingWidgets = false;
  this->UpdateResults();
}

void qRPLandmarkRegistrationPanel::OnTargetChanged() {
  if (this->UpdatingWidgets || !this->Logic || !this->Scene) return;
  auto* list = vtkRPFiducialListNode::SafeDownCast(
      this->Scene->GetNodeByID(this->TargetListCombo->currentData().toString().toStdString()));
  if (this->ObservedTargetList != list) {
    if (this->ObservedTargetList) this->ObservedTargetList->RemoveObserver(this->TargetListTag);
    this->ObservedTargetList = list;
    this->TargetListTag = list ? list->AddObserver(vtkCommand::ModifiedEvent, this,
                                                   &qRPLandmarkRegistrationPanel::OnTargetListModified)
                               : 0;
  }
  if (list && list->GetNumberOfControlPoints() > 0) {
    // The list's first point in world RAS, then in the "to" list's own coordinates.
    double world[4] = {0, 0, 0, 1}, local[4];
    list->GetNthControlPointPositionWorld(0, world);
    vtkNew<vtkMatrix4x4> toListFromWorld;
    if (vtkRPFiducialListNode* to = this->ToList()) to->GetMatrixTransformToWorld(toListFromWorld);
    toListFromWorld->Invert();
    toListFromWorld->MultiplyPoint(world, local);
    this->UpdatingWidgets = true;
    for (int k = 0; k < 3; ++k) this->Target[k]->setValue(local[k]);
    this->UseTarget->setChecked(true);
    this->UpdatingWidgets = false;
  }
  for (QDoubleSpinBox* box : this->Target) box->setEnabled(this->UseTarget->isChecked() && !list);
  if (this->UseTarget->isChecked()) {
    const double ras[3] = {this->Target[0]->value(), this->Target[1]->value(), this->Target[2]->value()};
    this->Logic->SetTarget(ras);
  } else {
    this->Logic->ClearTarget();
  }
  this->UpdateResults();
}

void qRPLandmarkRegistrationPanel::OnTargetListModified(vtkObject*, unsigned long, void*) { this->OnTargetChanged(); }

void qRPLandmarkRegistrationPanel::OnTargetFromSelectedRow() {
  vtkRPFiducialListNode* to = this->ToList();
  const int row = this->Table->currentRow();
  if (!to || row < 0 || row >= to->GetNumberOfControlPoints()) {
    this->SetStatus("select a row with an image point to use it as the target", true);
    return;
  }
  double ras[3];
  to->GetNthControlPointPosition(row, ras);
  this->UpdatingWidgets = true;
  for (int k = 0; k < 3; ++k) this->Target[k]->setValue(ras[k]);
  this->UseTarget->setChecked(true);
  this->UpdatingWidgets = false;
  this->OnTargetChanged();
}

bool qRPLandmarkRegistrationPanel::JumpSlicesToSelectedPoint() {
  const int row = this->Table->currentRow();
  vtkRPFiducialListNode* to = this->ToList();
  vtkRPFiducialListNode* from = this->FromList();
  // World RAS: the image point, else the physical point through the registration (if applied).
  vtkRPFiducialListNode* list = to && row >= 0 && row < to->GetNumberOfControlPoints() ? to
                                : from && row >= 0 && row < from->GetNumberOfControlPoints() ? from
                                                                                              : nullptr;
  if (!list || !this->Scene) return false;
  double ras[3];
  list->GetNthControlPointPositionWorld(row, ras);
  vtkRPSliceNode::JumpAllSlices(this->Scene, ras);
  return true;
}

void qRPLandmarkRegistrationPanel::OnRemoveSelectedPoint() {
  vtkRPFiducialListNode* from = this->FromList();
  const int row = this->Table->currentRow();
  if (!from || row < 0 || row >= from->GetNumberOfControlPoints()) {
    this->SetStatus("select a row with a physical point to remove it", true);
    return;
  }
  from->RemoveNthControlPoint(row);
}

// ---------------------------------------------------------------- actions

bool qRPLandmarkRegistrationPanel::CollectPoint() {
  vtkRPFiducialListNode* from = this->FromList();
  vtkRPLinearTransformNode* tool = this->ToolTransform();
  if (!from) {
    this->SetStatus("choose the physical (from) point list first", true);
    return false;
  }
  if (!tool) {
    this->SetStatus("choose the stylus tip transform (e.g. StylusTipToStylus)", true);
    return false;
  }
  // A tracked tool up the chain that the tracker does not see now has a stale pose: refuse.
  for (vtkRPLinearTransformNode* node = tool; node; node = node->GetParentTransformNode()) {
    auto* tracked = vtkRPTrackedToolNode::SafeDownCast(node);
    if (tracked && tracked->GetStatus() != vtkRPTrackedToolNode::StatusOK) {
      this->SetStatus(QString("not collected: %1 is not tracked (status %2); bring it into the tracker's view")
                          .arg(QString::fromStdString(tracked->GetName()),
                               vtkRPTrackedToolNode::GetStatusAsString(tracked->GetStatus())),
                      true);
      return false;
    }
  }
  // The tip is the tool frame's origin; express it in the list's own coordinates (tracker
  // coordinates when both sit under the same TrackerToRAS, or under none).
  vtkNew<vtkMatrix4x4> tipToWorld, listToWorld;
  tool->GetMatrixTransformToWorld(tipToWorld);
  from->GetMatrixTransformToWorld(listToWorld);
  listToWorld->Invert();
  vtkNew<vtkMatrix4x4> tipToList;
  vtkMatrix4x4::Multiply4x4(listToWorld, tipToWorld, tipToList);
  const double tip[3] = {tipToList->GetElement(0, 3), tipToList->GetElement(1, 3), tipToList->GetElement(2, 3)};
  std::string label;
  vtkRPFiducialListNode* to = this->ToList();
  const int next = from->GetNumberOfControlPoints();
  if (to && next < to->GetNumberOfControlPoints()) label = to->GetNthControlPoint(next).Label;
  const int index = from->AddControlPoint(tip, label);  // the logic recomputes when complete
  this->UpdateResults();
  if (to && next + 1 < to->GetNumberOfControlPoints()) {
    this->SetStatus(QString("collecting: %1 of %2 physical points (%3 at %4 mm); next: touch %5")
                        .arg(next + 1)
                        .arg(to->GetNumberOfControlPoints())
                        .arg(QString::fromStdString(from->GetNthControlPoint(index).Label), Point(tip),
                             QString::fromStdString(to->GetNthControlPoint(next + 1).Label)),
                    false);
  }
  return true;
}

bool qRPLandmarkRegistrationPanel::Register() {
  if (!this->Logic || !this->Logic->GetFromFiducials() || !this->Logic->GetToFiducials() ||
      !this->Logic->GetOutputTransform()) {
    this->SetStatus("choose both point lists and the output transform", true);
    return false;
  }
  const bool accepted = this->Logic->Update();
  this->UpdateResults();
  return accepted;
}

bool qRPLandmarkRegistrationPanel::ApplyToTools() {
  vtkRPLinearTransformNode* output = this->OutputTransform();
  if (!this->Scene || !output || output->GetAttribute("Registration.Status") != "accepted") {
    this->SetStatus("apply to tools: register first (the registration must be accepted)", true);
    return false;
  }
  // The roots of the tracked tool chains: the stylus tip's chain and every "...ToTracker" node.
  std::vector<vtkRPTransformableNode*> roots;
  if (vtkRPLinearTransformNode* tool = this->ToolTransform()) roots.push_back(RootOf(tool));
  for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPLinearTransformNode")) {
    if (rp::IsToolToTrackerName(node->GetName())) roots.push_back(RootOf(vtkRPTransformableNode::SafeDownCast(node)));
  }
  // The physical points too, so they are shown in image space over their image fiducials.
  if (vtkRPFiducialListNode* from = this->FromList()) roots.push_back(RootOf(from));
  QStringList moved;
  for (vtkRPTransformableNode* root : roots) {
    if (root == output || output->IsInParentChain(root)) continue;  // already under it, or a cycle
    if (root->SetAndObserveTransformNodeID(output->GetID())) moved << QString::fromStdString(root->GetName());
  }
  moved.removeDuplicates();
  this->UpdateResults();
  this->SetStatus(QString("%1; tools in image space%2")
                      .arg(QString::fromStdString(output->GetAttribute("Registration.Reason")),
                           moved.isEmpty() ? QString(" (already applied)") : ": " + moved.join(", ") + " under " +
                                                                                   QString::fromStdString(output->GetName())),
                  false);
  return true;
}

// ---------------------------------------------------------------- display

void qRPLandmarkRegistrationPanel::OnSceneChanged(vtkObject*, unsigned long event, void*) {
  // Node by node during an import or a close: once at its end instead.
  const bool batchEnd = event == vtkRPScene::EndImportEvent || event == vtkRPScene::EndCloseEvent;
  if (!batchEnd && this->Scene && (this->Scene->IsImporting() || this->Scene->IsClosing())) return;
  this->UpdateNodeCombos();
}

void qRPLandmarkRegistrationPanel::OnLogicOrListModified(vtkObject*, unsigned long, void*) {
  if (!this->UpdatingWidgets) this->UpdateResults();
}

void qRPLandmarkRegistrationPanel::SetStatus(const QString& text, bool error) {
  this->Status->setText(text);
  this->Status->setStyleSheet(error ? "color: #c00000; font-weight: bold;" : "");
}

QString qRPLandmarkRegistrationPanel::StatusText() const { return this->Status->text(); }
QString qRPLandmarkRegistrationPanel::FREText() const { return this->Fre->text(); }
QString qRPLandmarkRegistrationPanel::TREText() const { return this->Tre->text(); }

void qRPLandmarkRegistrationPanel::UpdateResults() {
  vtkRPFiducialListNode* from = this->FromList();
  vtkRPFiducialListNode* to = this->ToList();
  const int nFrom = from ? from->GetNumberOfControlPoints() : 0;
  const int nTo = to ? to->GetNumberOfControlPoints() : 0;
  const bool haveResult = this->Logic && this->Logic->GetNumberOfUpdates() > 0 &&
                          this->Logic->GetFromFiducials() == from && this->Logic->GetToFiducials() == to &&
                          this->Logic->GetOutputTransform() != nullptr && from && to;
  const rp::RegistrationAssessment* a = haveResult ? &this->Logic->GetLastAssessment() : nullptr;
  const double threshold = this->Logic ? this->Logic->GetFREThreshold() : 0;

  // Rows of the pairs the logic used (both points selected, equal counts), in order.
  std::vector<int> pairOfRow(static_cast<size_t>(std::max(nFrom, nTo)), -1);
  if (a && a->Solution.Ok && nFrom == nTo) {
    int pair = 0;
    for (int i = 0; i < nFrom; ++i)
      if (from->GetNthControlPoint(i).Selected && to->GetNthControlPoint(i).Selected) pairOfRow[static_cast<size_t>(i)] = pair++;
    if (pair != static_cast<int>(a->Solution.Residuals.size())) std::fill(pairOfRow.begin(), pairOfRow.end(), -1);
  }
  this->Table->setRowCount(static_cast<int>(pairOfRow.size()));
  auto cell = [this](int row, int column, const QString& text) {
    auto* item = this->Table->item(row, column);
    if (!item) {
      item = new QTableWidgetItem;
      this->Table->setItem(row, column, item);
    }
    item->setText(text);
    item->setBackground(QBrush());
    return item;
  };
  for (int row = 0; row < static_cast<int>(pairOfRow.size()); ++row) {
    double p[3];
    const std::string label = row < nTo ? to->GetNthControlPoint(row).Label : from->GetNthControlPoint(row).Label;
    cell(row, LabelColumn, QString::fromStdString(label));
    if (row < nFrom) from->GetNthControlPointPosition(row, p);
    cell(row, FromColumn, row < nFrom ? Point(p) : QString("(to collect)"));
    if (row < nTo) to->GetNthControlPointPosition(row, p);
    cell(row, ToColumn, row < nTo ? Point(p) : QString("(no image point)"));
    const int pair = pairOfRow[static_cast<size_t>(row)];
    const double residual = pair >= 0 ? a->Solution.Residuals[static_cast<size_t>(pair)] : NAN;
    const double loo = pair >= 0 && static_cast<size_t>(pair) < a->LeaveOneOut.size()
                           ? a->LeaveOneOut[static_cast<size_t>(pair)]
                           : NAN;
    QTableWidgetItem* r = cell(row, ResidualColumn, Mm(residual));
    if (pair >= 0) r->setBackground(ResidualColor(residual, threshold));
    QTableWidgetItem* l = cell(row, LeaveOneOutColumn, Mm(loo));
    if (pair >= 0) l->setBackground(ResidualColor(loo, threshold));
  }

  if (!a) {
    this->Fre->setText("FRE: –");
    this->Tre->setText("Predicted TRE: –");
    this->Warnings->clear();
    if (!from || !to || !this->OutputTransform())
      this->SetStatus("choose the physical and image point lists and the output transform", false);
    return;
  }
  const double fle = this->Logic->GetFLE();
  this->Fre->setText(QString("FRE: %1 mm   (expected %2 mm from FLE %3 mm; FRE is not the accuracy)")
                         .arg(Mm(a->Solution.FRE), Mm(a->ExpectedFRE), Mm(fle)));
  QString tre;
  if (std::isfinite(a->PredictedTREAtTarget))
    tre = QString("Predicted TRE at the target: %1 mm").arg(Mm(a->PredictedTREAtTarget));
  else
    tre = QString("Predicted TRE at the centroid: %1 mm").arg(Mm(a->PredictedTREAtCentroid));
  tre += QString("   (largest at a fiducial: %1 mm)").arg(Mm(a->MaxPredictedTREAtFiducials));
  this->Tre->setText(tre);
  QStringList warnings;
  for (const auto& w : a->Warnings) warnings << QString::fromStdString(w);
  this->Warnings->setText(warnings.join("\n"));
  if (nFrom < nTo) {
    this->SetStatus(QString("collecting: %1 of %2 physical points; next: touch %3")
                        .arg(nFrom)
                        .arg(nTo)
                        .arg(QString::fromStdString(to->GetNthControlPoint(nFrom).Label)),
                    false);
    return;
  }
  this->SetStatus(QString::fromStdString(a->Reason), !a->Accepted);
  if (a->Accepted) this->Status->setStyleSheet("color: #107010; font-weight: bold;");
}
