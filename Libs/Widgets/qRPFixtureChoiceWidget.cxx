#include "qRPFixtureChoiceWidget.h"

#include <cmath>

#include <QCheckBox>
#include <QComboBox>
#include <QSignalBlocker>
#include <QStringList>
#include <QTimer>

#include "rpFixtureRenderer.h"
#include "rpSceneNodesWatch.h"
#include "ui_qRPFixtureChoiceWidget.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

namespace {
// The surface combo's item data: a cut plane's or a model's node ID behind its kind.
const QString PlanePrefix = "plane:", ModelPrefix = "model:";

QString NodeLabel(vtkRPNode* node) {
  return QString::fromStdString(node->GetName().empty() ? node->GetID() : node->GetName());
}

// Fills `combo` with `items` (label, data), keeping the current data when it is still there.
void Refill(QComboBox* combo, const QList<QPair<QString, QString>>& items) {
  const QString current = combo->currentData().toString();
  const QSignalBlocker block(combo);
  combo->clear();
  for (const auto& item : items) combo->addItem(item.first, item.second);
  const int index = combo->findData(current);
  combo->setCurrentIndex(index >= 0 ? index : (combo->count() > 0 ? 0 : -1));
}

QString Mm(double mm) { return QString("%1 mm").arg(mm, 0, 'f', 2); }

// One fixture's line: what it is and, while running, what it does.
QString FixtureLine(const rp::FixtureEntry& e, const rp::FixtureReport* r) {
  const rp::VirtualFixture& f = *e.Fixture;
  const QString name = "'" + QString::fromStdString(f.Name()) + "'";
  QString what, now;
  switch (f.Kind()) {
    case rp::FixtureKind::AxisGuidance:
      what = "axis guidance on " + name + QString(" (captures within %1)").arg(Mm(e.Tuning.Capture));
      if (r) now = r->Engaged ? "ENGAGED, " + Mm(r->Distance) + " off the axis" : "free, " + Mm(r->Distance) + " off the axis";
      break;
    case rp::FixtureKind::DepthStop:
      what = "depth stop at the target of " + name;
      if (r) now = !r->Armed ? "waiting: the tool is past the target depth"
                   : r->Contact ? "AT THE STOP"
                                : Mm(r->Distance) + " to the target depth";
      break;
    case rp::FixtureKind::ForbiddenRegion:
      what = "forbidden region " + name;
      if (r) now = !r->Armed ? "waiting: the tool is inside it" : (r->Contact ? "AT THE WALL, " : "") + Mm(r->Distance) + " from it";
      break;
    case rp::FixtureKind::SurfaceConstraint:
      what = "surface constraint on " + name + QString(" (within %1)").arg(Mm(e.Tuning.Capture));
      if (r) now = r->Engaged ? "HOLDING, " + Mm(r->Distance) + " from the surface" : "free, " + Mm(r->Distance) + " from the surface";
      break;
  }
  if (!r) return what;
  if (!std::isfinite(r->Distance)) now = "not measured yet";
  const double force = rp::Norm(r->Force);
  if (force >= 0.005) now += QString(", %1 N").arg(force, 0, 'f', 2);
  if (r->Weight > 0 && r->Weight < 1) now += QString(" (fading, %1 %)").arg(100 * r->Weight, 0, 'f', 0);
  return what + ": " + now;
}
}  // namespace

qRPFixtureChoiceWidget::qRPFixtureChoiceWidget(QWidget* parent)
    : QGroupBox(parent), UI(std::make_unique<Ui::qRPFixtureChoiceWidget>()) {
  this->UI->setupUi(this);
  this->WatchTimer = new QTimer(this);
  this->WatchTimer->setInterval(250);  // node lists: a quarter second is soon enough
  connect(this->WatchTimer, &QTimer::timeout, this, [this] {
    if (this->Watch && this->Watch->TakeChanged()) this->RefreshNodes();
    // A plan node moved (a trajectory dragged) while fixtures act: build them again (their ids
    // stay, so the servo carries the fades over and the force follows within the device's rate).
    const bool acting = this->Applied.Axis || this->Applied.Depth || this->Applied.Forbidden || this->Applied.Surface;
    if (acting && this->PlanSignature() != this->AppliedSignature) this->ApplyChoice();
  });
  for (QCheckBox* box : {this->UI->AxisCheck, this->UI->DepthCheck, this->UI->ForbiddenCheck, this->UI->SurfaceCheck})
    connect(box, &QCheckBox::toggled, this, [this](bool) { this->OnChanged(); });
  for (QComboBox* combo : {this->UI->TrajectoryCombo, this->UI->SurfaceCombo})
    connect(combo, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) { this->OnChanged(); });
}

qRPFixtureChoiceWidget::~qRPFixtureChoiceWidget() = default;

QComboBox* qRPFixtureChoiceWidget::TrajectoryComboBox() const { return this->UI->TrajectoryCombo; }
QComboBox* qRPFixtureChoiceWidget::SurfaceComboBox() const { return this->UI->SurfaceCombo; }
QCheckBox* qRPFixtureChoiceWidget::AxisCheckBox() const { return this->UI->AxisCheck; }
QCheckBox* qRPFixtureChoiceWidget::DepthCheckBox() const { return this->UI->DepthCheck; }
QCheckBox* qRPFixtureChoiceWidget::ForbiddenCheckBox() const { return this->UI->ForbiddenCheck; }
QCheckBox* qRPFixtureChoiceWidget::SurfaceCheckBox() const { return this->UI->SurfaceCheck; }
QString qRPFixtureChoiceWidget::StatusText() const { return this->UI->StatusLabel->text(); }

void qRPFixtureChoiceWidget::Setup(vtkRPScene* scene, ApplyFunction apply, InUseFunction inUse) {
  this->Apply = std::move(apply);
  this->InUse = std::move(inUse);
  this->Scene = scene;
  this->Watch = std::make_unique<rp::SceneNodesWatch>(scene);
  this->WatchTimer->start();
  this->RefreshNodes();
}

void qRPFixtureChoiceWidget::RefreshNodes() {
  QList<QPair<QString, QString>> trajectories, surfaces;
  if (this->Scene) {
    for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPTrajectoryNode"))
      trajectories.append({NodeLabel(node), QString::fromStdString(node->GetID())});
    for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPCutPlaneNode"))
      surfaces.append({"cut plane " + NodeLabel(node), PlanePrefix + QString::fromStdString(node->GetID())});
    for (vtkRPNode* node : this->Scene->GetNodesByClass("vtkRPModelNode"))
      surfaces.append({"model " + NodeLabel(node), ModelPrefix + QString::fromStdString(node->GetID())});
  }
  const QString trajectory = this->UI->TrajectoryCombo->currentData().toString();
  const QString surface = this->UI->SurfaceCombo->currentData().toString();
  Refill(this->UI->TrajectoryCombo, trajectories);
  Refill(this->UI->SurfaceCombo, surfaces);
  // The fixtures follow a node that left the scene: apply again (which names what is missing).
  if (this->UI->TrajectoryCombo->currentData().toString() != trajectory ||
      this->UI->SurfaceCombo->currentData().toString() != surface)
    this->OnChanged();
}

rp::PlanFixtureChoice qRPFixtureChoiceWidget::Choice() const {
  rp::PlanFixtureChoice c;
  c.Axis = this->UI->AxisCheck->isChecked();
  c.Depth = this->UI->DepthCheck->isChecked();
  c.Forbidden = this->UI->ForbiddenCheck->isChecked();
  c.Surface = this->UI->SurfaceCheck->isChecked();
  c.Trajectory = this->UI->TrajectoryCombo->currentData().toString().toStdString();
  const QString surface = this->UI->SurfaceCombo->currentData().toString();
  if (surface.startsWith(PlanePrefix)) c.SurfacePlane = surface.mid(PlanePrefix.size()).toStdString();
  if (surface.startsWith(ModelPrefix)) c.SurfaceModelNode = surface.mid(ModelPrefix.size()).toStdString();
  return c;
}

void qRPFixtureChoiceWidget::SetBoxes(const rp::PlanFixtureChoice& c) {
  const QSignalBlocker a(this->UI->AxisCheck), d(this->UI->DepthCheck), f(this->UI->ForbiddenCheck), s(this->UI->SurfaceCheck);
  this->UI->AxisCheck->setChecked(c.Axis);
  this->UI->DepthCheck->setChecked(c.Depth);
  this->UI->ForbiddenCheck->setChecked(c.Forbidden);
  this->UI->SurfaceCheck->setChecked(c.Surface);
}

unsigned long qRPFixtureChoiceWidget::PlanSignature() const {
  unsigned long signature = 0;
  if (this->Scene)
    for (const char* type : {"vtkRPTrajectoryNode", "vtkRPCutPlaneNode", "vtkRPModelNode"})
      for (vtkRPNode* node : this->Scene->GetNodesByClass(type)) signature += node->GetMTime();
  return signature;
}

bool qRPFixtureChoiceWidget::ApplyChoice() {
  if (!this->Apply) return false;
  this->AppliedSignature = this->PlanSignature();  // tried with the plan as it is now
  const rp::PlanFixtureChoice choice = this->Choice();
  std::string error;
  if (!this->Apply(choice, error)) {
    this->SetBoxes(this->Applied);  // the fixtures in use stay
    this->Refusal = QString::fromStdString(error);
    this->UI->StatusLabel->setText(this->Refusal);
    this->UI->StatusLabel->setStyleSheet("color: #c0392b;");
    return false;
  }
  this->Applied = choice;
  this->Refusal.clear();
  this->UI->StatusLabel->setStyleSheet("");
  this->ShowFixtures(nullptr);  // while running, the panel's next display tick adds the servo's reports
  emit this->FixturesChanged();
  return true;
}

void qRPFixtureChoiceWidget::OnChanged() {
  const rp::PlanFixtureChoice c = this->Choice();
  const bool none = !c.Axis && !c.Depth && !c.Forbidden && !c.Surface;
  if (none && !this->Applied.Axis && !this->Applied.Depth && !this->Applied.Forbidden && !this->Applied.Surface) return;
  this->ApplyChoice();
}

void qRPFixtureChoiceWidget::ShowFixtures(const rp::FixtureStatus* running) {
  // A refusal stays readable (above the fixtures still in use) until the next change.
  const std::shared_ptr<const rp::FixtureSet> set = this->InUse ? this->InUse() : nullptr;
  const QString fixtures = DescribeFixtures(set.get(), running);
  this->UI->StatusLabel->setText(this->Refusal.isEmpty() ? fixtures : this->Refusal + "\nin use: " + fixtures);
}

QString qRPFixtureChoiceWidget::DescribeFixtures(const rp::FixtureSet* set, const rp::FixtureStatus* running) {
  QStringList lines;
  for (int i = 0; set && i < set->Count(); ++i) {
    const rp::FixtureEntry& e = set->Entries[size_t(i)];
    if (!e.Enabled) continue;
    const rp::FixtureReport* report = nullptr;
    for (int j = 0; running && j < running->Count; ++j)
      if (running->Fixtures[j].Id == e.Fixture->Id()) report = &running->Fixtures[j];
    lines << FixtureLine(e, report);
  }
  return lines.isEmpty() ? QString("no fixture acts (free hand)") : lines.join("\n");
}
