#include "qRPDrillingPanel.h"

#include <algorithm>
#include <cmath>

#include <QApplication>
#include <QDateTime>
#include <QDir>
#include <QFileDialog>
#include <QTimer>

#include <vtkPolyData.h>

#include "rpDrillSession.h"
#include "rpGuidedDrill.h"
#include "rpHapticSceneBridge.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTransformableNode.h"

namespace {
QStringList Checked(const QListWidget* list) {
  QStringList ids;
  for (int i = 0; i < list->count(); ++i)
    if (list->item(i)->checkState() == Qt::Checked) ids << list->item(i)->data(Qt::UserRole).toString();
  return ids;
}
}  // namespace

qRPDrillingPanel::qRPDrillingPanel(vtkRPDrillingLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  this->Burr[0] = this->BurrR;
  this->Burr[1] = this->BurrA;
  this->Burr[2] = this->BurrS;
  this->RecordPath->setText(QDir::tempPath() + "/roboplan-drill-" +
                            QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss") + ".txt");
  this->Guidance->Setup(
      logic ? logic->GetScene() : nullptr,
      [this](const rp::PlanFixtureChoice& choice, std::string& error) { return this->Logic && this->Logic->SetPlanFixtures(choice, error); },
      [this] { return this->Logic ? this->Logic->GetPlanFixtures() : nullptr; });
  for (QDoubleSpinBox* spin : this->Burr)
    connect(spin, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double) { this->SendBurrPosition(); });

  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);  // 30 Hz display rate
  connect(this->Timer, &QTimer::timeout, this, &qRPDrillingPanel::Update);
  connect(this->Segmentation, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) { this->RefreshChoices(); });
  connect(this->Build, &QPushButton::clicked, this, [this] { this->BuildBone(); });
  connect(this->StartStop, &QPushButton::clicked, this, [this] { this->IsRunning() ? this->Stop() : (void)this->Start(); });
  connect(this->BurrOn, &QPushButton::toggled, this, [this](bool on) {
    if (this->Logic) this->Logic->SetBurrOn(on);
    this->BurrOn->setText(on ? "Burr off" : "Burr on");
  });
  connect(this->UndoStroke, &QPushButton::clicked, this, [this] {
    if (this->Logic) this->Logic->Undo();
  });
  connect(this->ResetBone, &QPushButton::clicked, this, [this] {
    if (this->Logic) this->Logic->ResetBone();
  });
  connect(this->Radius, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double r) {
    if (this->Logic) this->Logic->SetBurrRadius(r);
  });
  connect(this->Rpm, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double rpm) {
    if (this->Logic) this->Logic->SetRpm(rpm);
  });
  connect(this->Drive, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (this->Logic) this->Logic->SetFollowedNodeID(this->Drive->currentData().toString().toStdString());
    for (QDoubleSpinBox* spin : this->Burr) spin->setEnabled(this->Drive->currentData().toString().isEmpty());
  });
  connect(this->Picture, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save tunnel picture", QDir::homePath() + "/tunnel.png", "PNG (*.png)");
    if (!path.isEmpty()) this->SavePicture(path);
  });
  connect(this->Execute, &QPushButton::clicked, this, [this] { this->ExecutePlan(); });
  if (this->Logic) {
    this->Logic->SetBurrRadius(this->Radius->value());
    this->Logic->SetRpm(this->Rpm->value());
  }
  this->RefreshChoices();
}

qRPDrillingPanel::~qRPDrillingPanel() { this->Stop(); }

QString qRPDrillingPanel::ExecutionText() const { return this->ExecutionInfo->text(); }

namespace {
QString ScoreText(const rp::GuidedDrillResult& r, const QString& fixtures) {
  const rp::ExecutionScore& s = r.Score;
  return QString("%1: entry %2 mm, tip %3 mm, angle %4°, depth error %5 mm, max deviation %6 mm; "
                 "forbidden region entered: %7; drilling %8 s")
      .arg(fixtures)
      .arg(s.EntryOffsetMm, 0, 'f', 2)
      .arg(s.TipOffsetMm, 0, 'f', 2)
      .arg(s.AngleDeg, 0, 'f', 2)
      .arg(s.DepthErrorMm, 0, 'f', 2)
      .arg(s.MaxDeviationMm, 0, 'f', 2)
      .arg(r.EnteredForbidden ? "YES" : "no")
      .arg(r.DrillSeconds, 0, 'f', 1);
}
}  // namespace

bool qRPDrillingPanel::ExecutePlan() {
  if (this->Logic == nullptr) return false;
  this->Stop();
  auto refuse = [this](const QString& why) {
    this->Last = rp::GuidedDrillResult{};
    this->ExecutionInfo->setText(why);
    return false;
  };
  if (this->FreshBone->isChecked() && !Checked(this->BoneSegments).isEmpty() && !this->BuildBone())
    return refuse("the bone: " + this->BoneText());
  if (!this->Logic->HasBone()) return refuse("build the voxel bone first");
  std::string error;
  const std::shared_ptr<const rp::PlanSnapshot> plan = rp::SnapshotPlan(this->Logic->GetScene(), error);
  if (plan && plan->Trajectories.empty()) return refuse("the scene has no complete trajectory (entry and target) to execute");
  const rp::PlanFixtureChoice choice = this->Guidance->Choice();
  const rp::TrajectorySnapshot* trajectory = plan ? rp::ChooseTrajectory(*plan, choice.Trajectory, error) : nullptr;
  if (trajectory == nullptr) return refuse(QString::fromStdString(error));
  rp::GuidedDrillOptions options;
  options.BurrRadiusMm = this->Radius->value();
  options.Rpm = this->Rpm->value();
  options.SpeedMmPerS = this->HandSpeed->value();
  options.Noise.TremorMm = this->Tremor->value();
  options.Noise.DriftMmPerS = this->Drift->value();
  options.Noise.Seed = static_cast<uint64_t>(this->Seed->value());
  // The run takes seconds on this thread (it drills the logic's bone and its model node): the
  // window repaints and the bar moves, the panel's own input waits.
  options.Progress = [this](double fraction, const std::string&) {
    this->Progress->setValue(static_cast<int>(1000 * fraction));
    QApplication::processEvents(QEventLoop::ExcludeUserInputEvents);
  };
  this->setEnabled(false);
  this->Progress->setValue(0);
  this->ExecutionInfo->setText("drilling '" + QString::fromStdString(trajectory->Name) + "' with the simulated hand…");
  rp::GuidedDrillResult& result = this->Last;
  result = rp::GuidedDrillResult{};
  const bool done = rp::DrillPlannedTrajectory(this->Logic, *plan, *trajectory, choice, options, result, error);
  result.Run.Records.clear();  // every tick's record: the path and the score are what is kept
  this->setEnabled(true);
  this->Progress->setValue(1000);
  // The run handed its own fixtures to the logic: the Guidance group's again for the next session.
  std::string ignored;
  if (this->Logic->GetPlanFixtures() == nullptr) this->Logic->SetPlanFixtures(this->Guidance->Choice(), ignored);
  if (!done) return refuse(QString::fromStdString(error));
  const QString fixtures = qRPFixtureChoiceWidget::DescribeFixtures(result.Fixtures.get(), nullptr);
  this->ExecutionInfo->setText(ScoreText(result, "'" + QString::fromStdString(trajectory->Name) + "', " +
                                                     (result.Fixtures ? fixtures.split("\n").join(", ") : "free hand")));
  return true;
}

bool qRPDrillingPanel::IsRunning() const { return this->Logic && this->Logic->IsRunning(); }
QString qRPDrillingPanel::StatusText() const { return this->State->text(); }
QString qRPDrillingPanel::BoneText() const { return this->BoneInfo->text(); }
QString qRPDrillingPanel::RemovedText() const { return this->RemovedInfo->text(); }
QString qRPDrillingPanel::ProtectedText() const { return this->ProtectedInfo->text(); }

void qRPDrillingPanel::RefreshChoices() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (scene == nullptr) return;
  const QString chosen = this->Segmentation->currentData().toString();
  {
    const QSignalBlocker block(this->Segmentation);
    this->Segmentation->clear();
    for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode"))
      this->Segmentation->addItem(QString::fromStdString(node->GetName().empty() ? node->GetID() : node->GetName()), QString::fromStdString(node->GetID()));
    const int index = this->Segmentation->findData(chosen);
    this->Segmentation->setCurrentIndex(index >= 0 ? index : 0);
  }
  const QString ct = this->CT->currentData().toString();
  this->CT->clear();
  this->CT->addItem("(none: tissue class)", QString());
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPScalarVolumeNode"))
    this->CT->addItem(QString::fromStdString(node->GetName().empty() ? node->GetID() : node->GetName()), QString::fromStdString(node->GetID()));
  if (this->CT->findData(ct) >= 0) this->CT->setCurrentIndex(this->CT->findData(ct));
  const QString drive = this->Drive->currentData().toString();
  {
    const QSignalBlocker block(this->Drive);
    this->Drive->clear();
    this->Drive->addItem("Panel (simulated device)", QString());
    for (vtkRPNode* node : scene->GetNodesByClass("vtkRPTrackedToolNode")) {
      const std::string& name = node->GetName();
      if (name == rp::HapticInterfacePointName || name == rp::HapticProxyName) continue;  // the burr's own output
      this->Drive->addItem(QString::fromStdString(name.empty() ? node->GetID() : name), QString::fromStdString(node->GetID()));
    }
    if (this->Drive->findData(drive) >= 0) this->Drive->setCurrentIndex(this->Drive->findData(drive));
  }
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(scene->GetNodeByID(this->Segmentation->currentData().toString().toStdString()));
  const QStringList bone = Checked(this->BoneSegments), guarded = Checked(this->ProtectedSegments);
  this->BoneSegments->clear();
  this->ProtectedSegments->clear();
  if (segmentation == nullptr) return;
  for (const auto& s : segmentation->GetSegments()) {
    const QString id = QString::fromStdString(s.ID);
    const QString label = QString::fromStdString(s.Name.empty() ? s.ID : s.Name) +
                          (s.TissueClass.empty() ? QString() : " (" + QString::fromStdString(s.TissueClass) + ")");
    auto* b = new QListWidgetItem(label, this->BoneSegments);
    b->setData(Qt::UserRole, id);
    b->setFlags(b->flags() | Qt::ItemIsUserCheckable);
    b->setCheckState(bone.contains(id) ? Qt::Checked : Qt::Unchecked);
    auto* p = new QListWidgetItem(label, this->ProtectedSegments);
    p->setData(Qt::UserRole, id);
    p->setFlags(p->flags() | Qt::ItemIsUserCheckable);
    p->setCheckState(guarded.contains(id) ? Qt::Checked : Qt::Unchecked);
  }
}

bool qRPDrillingPanel::BuildBone() {
  if (this->Logic == nullptr) return false;
  this->Stop();
  vtkRPDrillingLogic::BoneChoice choice;
  choice.SegmentationID = this->Segmentation->currentData().toString().toStdString();
  for (const QString& id : Checked(this->BoneSegments)) choice.BoneSegments.push_back(id.toStdString());
  for (const QString& id : Checked(this->ProtectedSegments)) choice.ProtectedSegments.push_back(id.toStdString());
  choice.CTVolumeID = this->CT->currentData().toString().toStdString();
  choice.VoxelMm = this->Voxel->value();
  if (choice.BoneSegments.empty()) {
    this->BoneInfo->setText("tick the bone segment(s) to drill");
    return false;
  }
  std::string error;
  QApplication::setOverrideCursor(Qt::WaitCursor);
  const bool built = this->Logic->BuildBone(choice, error);
  QApplication::restoreOverrideCursor();
  if (!built) {
    this->BoneInfo->setText(QString::fromStdString(error));
    return false;
  }
  const rp::DrillBoneReport& r = this->Logic->GetBoneReport();
  const auto tissues = this->Logic->GetTissueNames();
  QString text = QString("%1 blocks, %2 MB, %3 s").arg(r.StoredBlocks).arg(r.MemoryMB, 0, 'f', 1).arg(r.Seconds, 0, 'f', 2);
  for (size_t m = 0; m < tissues.size() && m < r.VolumeMm3.size(); ++m)
    if (r.VolumeMm3[m] > 0) text += QString("; %1 %2 cm³").arg(QString::fromStdString(tissues[m])).arg(r.VolumeMm3[m] / 1000, 0, 'f', 1);
  this->BoneInfo->setText(text);
  this->FitBurrRange();
  return true;
}

void qRPDrillingPanel::FitBurrRange() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  auto* model = scene ? vtkRPModelNode::SafeDownCast(scene->GetNodeByID(this->Logic->GetDrilledModelID())) : nullptr;
  if (model == nullptr || model->GetPolyData() == nullptr || model->GetPolyData()->GetNumberOfPoints() == 0) return;
  double b[6];
  model->GetPolyData()->GetBounds(b);
  for (int k = 0; k < 3; ++k) {
    const QSignalBlocker block(this->Burr[k]);
    this->Burr[k]->setRange(b[2 * k] - 30, b[2 * k + 1] + 30);
    // Start above the bone (S), centred in R and A: out of contact.
    this->Burr[k]->setValue(k == 2 ? b[5] + 10 : 0.5 * (b[2 * k] + b[2 * k + 1]));
  }
}

void qRPDrillingPanel::SendBurrPosition() {
  if (this->Logic == nullptr) return;
  const double ras[3] = {this->Burr[0]->value(), this->Burr[1]->value(), this->Burr[2]->value()};
  this->Logic->SetSimulatedBurrPosition(ras);
}

bool qRPDrillingPanel::Start() {
  if (this->Logic == nullptr) return false;
  if (this->IsRunning()) return true;
  if (!this->Logic->HasBone() && !this->BuildBone()) {
    this->State->setText("build the voxel bone first");
    return false;
  }
  this->SendBurrPosition();  // the burr starts where the spin boxes say
  this->Logic->SetRecordPath(this->RecordPath->text().trimmed().toStdString());
  this->Logic->SetBurrOn(this->BurrOn->isChecked());
  std::string error;
  if (!this->Logic->StartSimulated(error)) {
    this->State->setText(QString::fromStdString(error));
    return false;
  }
  this->RecordPath->setEnabled(false);
  this->Build->setEnabled(false);
  this->StartStop->setText("Stop drilling");
  this->Timer->start();
  this->Update();
  return true;
}

void qRPDrillingPanel::Stop() {
  if (this->Timer) this->Timer->stop();
  const bool wasRunning = this->IsRunning();
  if (this->Logic) {
    this->Update();
    this->Logic->Stop();  // zero force, join the threads, flush the recording
  }
  this->StartStop->setText("Start drilling");
  this->RecordPath->setEnabled(true);
  this->Build->setEnabled(true);
  if (this->Logic) this->Guidance->ShowFixtures(nullptr);
  if (wasRunning)
    this->State->setText(this->Logic->GetRecordPath().empty()
                             ? QString("stopped")
                             : "stopped; drill path " + QString::fromStdString(this->Logic->GetRecordPath()));
}

void qRPDrillingPanel::Update() {
  if (!this->IsRunning()) return;
  this->Logic->Update();
  rp::DrillState s;
  if (!this->Logic->ReadState(s)) return;
  const auto tissues = this->Logic->GetTissueNames();
  QString state = s.BurrOn ? "burr on" : "burr off";
  if (s.Stopped) state = "STOPPED: the burr reached a protected structure (switch it off and on)";
  else if (s.Cutting) state += QString(", cutting %1 at %2 mm/s").arg(s.CutMaterial >= 0 ? QString::fromStdString(tissues[size_t(s.CutMaterial)]) : "").arg(s.FeedMmPerS, 0, 'f', 1);
  else if (s.Contact) state += ", touching bone";
  if (s.Restoring) state += ", restoring";
  if (s.Embedded) state += ", inside bone (move out)";
  this->State->setText(state);
  this->Removed = s.RemovedTotalMm3;
  QString removed = QString("%1 mm³").arg(s.RemovedTotalMm3, 0, 'f', 1);
  for (size_t m = 0; m < tissues.size(); ++m)
    if (s.RemovedMm3[m] > 0) removed += QString(", %1 %2").arg(QString::fromStdString(tissues[m])).arg(s.RemovedMm3[m], 0, 'f', 1);
  removed += QString(" (%1 undoable stroke%2)").arg(s.UndoableStrokes).arg(s.UndoableStrokes == 1 ? "" : "s");
  this->RemovedInfo->setText(removed);
  this->Warning = s.Warning;
  if (std::isfinite(s.ProtectedDistance)) {
    this->ProtectedInfo->setText(QString("%1 mm (closest %2 mm)").arg(s.ProtectedDistance, 0, 'f', 2).arg(s.ClosestApproach, 0, 'f', 2));
    this->ProtectedInfo->setStyleSheet(s.Warning ? "color: white; background: #c0392b; font-weight: bold" : "color: #1e8449");
  } else {
    this->ProtectedInfo->setText("none");
    this->ProtectedInfo->setStyleSheet("");
  }
  this->ForceInfo->setText(QString("%1 N%2").arg(rp::Norm(s.Force), 0, 'f', 2).arg(s.Clamped ? " (device maximum)" : ""));
  this->Guidance->ShowFixtures(&s.Fixtures);
  if (rp::DrillSession* session = this->Logic->GetSession()) {
    const auto frames = session->Display().Frames();
    std::vector<double> ms;
    for (const auto& f : frames) ms.push_back(f.ContourMs);
    std::sort(ms.begin(), ms.end());
    const double p95 = ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, size_t(0.95 * ms.size()))];
    this->Timing->setText(QString("%1 us / %2 ms").arg(session->Scheduler().Stats().Compute.P99Us, 0, 'f', 1).arg(p95, 0, 'f', 2));
  }
}

bool qRPDrillingPanel::SavePicture(const QString& path) {
  if (this->Logic == nullptr) return false;
  std::string error;
  if (!this->Logic->SaveTunnelPicture(path.toStdString(), error)) {
    this->State->setText(QString::fromStdString(error));
    return false;
  }
  this->State->setText("tunnel picture: " + path);
  return true;
}
