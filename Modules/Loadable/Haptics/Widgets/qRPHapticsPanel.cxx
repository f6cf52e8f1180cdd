#include "qRPHapticsPanel.h"

#include <cmath>

#include <QApplication>
#include <QDateTime>
#include <QDir>
#include <QTimer>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include "rpDeviceProfiles.h"
#include "rpHapticSceneBridge.h"
#include "rpHapticSession.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

qRPHapticsPanel::qRPHapticsPanel(vtkRPHapticsLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  this->Stylus[0] = this->StylusR;
  this->Stylus[1] = this->StylusA;
  this->Stylus[2] = this->StylusS;
  for (const rp::DeviceProfile& profile : rp::DeviceProfiles())
    this->Device->addItem(QString::fromStdString(profile.Info.Name), QString::fromStdString(profile.Key));
  this->Device->setCurrentIndex(std::max(0, this->Device->findData(QString::fromStdString(logic ? logic->GetDeviceProfile() : ""))));
  this->LogPath->setText(QDir::tempPath() + "/roboplan-haptics-" +
                         QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss") + ".csv");
  this->Clamps->setVisible(false);  // shown when the device clamps a tissue (Update)
  this->FollowProxy->SetScene(logic ? logic->GetScene() : nullptr);
  this->Guidance->Setup(
      logic ? logic->GetScene() : nullptr,
      [this](const rp::PlanFixtureChoice& choice, std::string& error) { return this->Logic && this->Logic->SetPlanFixtures(choice, error); },
      [this] { return this->Logic ? this->Logic->GetPlanFixtures() : nullptr; });
  for (QDoubleSpinBox* spin : this->Stylus)
    connect(spin, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double) { this->SendStylusPose(); });
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);  // 30 Hz display rate
  connect(this->Timer, &QTimer::timeout, this, &qRPHapticsPanel::Update);
  connect(this->StartButton, &QPushButton::clicked, this, [this] {
    if (this->IsRunning())
      this->Stop();
    else
      this->Start();
  });
  connect(this->Drive, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    const QString id = this->Drive->currentData().toString();
    if (this->Logic) this->Logic->SetFollowedNodeID(id.toStdString());
    for (QDoubleSpinBox* spin : this->Stylus) spin->setEnabled(id.isEmpty());
  });
  this->RefreshDrives();
  this->FitRangesToHapticModels();
}

void qRPHapticsPanel::RefreshDrives() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  const QString chosen = this->Drive->currentData().toString();
  const QSignalBlocker block(this->Drive);
  this->Drive->clear();
  this->Drive->addItem("Panel (simulated device)", QString());
  if (scene != nullptr) {
    for (vtkRPNode* node : scene->GetNodesByClass("vtkRPTrackedToolNode")) {
      const std::string& name = node->GetName();
      if (name == rp::HapticInterfacePointName || name == rp::HapticProxyName) continue;  // the servo's own output
      this->Drive->addItem(QString::fromStdString(name.empty() ? node->GetID() : name), QString::fromStdString(node->GetID()));
    }
  }
  const int index = this->Drive->findData(chosen);
  this->Drive->setCurrentIndex(index >= 0 ? index : 0);
}

qRPHapticsPanel::~qRPHapticsPanel() {
  // Closing the viewer: zero the device force and commit the session log.
  this->Stop();
}

bool qRPHapticsPanel::IsRunning() const { return this->Logic && this->Logic->IsRunning(); }
QString qRPHapticsPanel::StatusText() const { return this->State->text(); }
QString qRPHapticsPanel::TissueText() const { return this->Tissue->text(); }
QString qRPHapticsPanel::ForceText() const { return this->Force->text(); }
QString qRPHapticsPanel::PenetrationText() const { return this->Penetration->text(); }
QString qRPHapticsPanel::TimingText() const { return this->Timing->text(); }
QString qRPHapticsPanel::ClampText() const { return this->Clamps->text(); }

void qRPHapticsPanel::FitRangesToHapticModels() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (scene == nullptr) return;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* model = vtkRPModelNode::SafeDownCast(node);
    if (model == nullptr || !model->GetHaptic() || model->GetPolyData() == nullptr ||
        model->GetPolyData()->GetNumberOfPoints() == 0)
      continue;
    double b[6];
    model->GetPolyData()->GetBounds(b);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::fmin(lo[k], b[2 * k]);
      hi[k] = std::fmax(hi[k], b[2 * k + 1]);
    }
  }
  if (!(lo[0] <= hi[0])) return;  // no haptic model: keep the default range
  for (int k = 0; k < 3; ++k) {
    const QSignalBlocker block(this->Stylus[k]);
    this->Stylus[k]->setRange(lo[k] - 20, hi[k] + 20);
  }
  // Start above the models (S max), centred in R and A: out of contact.
  const QSignalBlocker b0(this->Stylus[0]), b1(this->Stylus[1]), b2(this->Stylus[2]);
  this->Stylus[0]->setValue(0.5 * (lo[0] + hi[0]));
  this->Stylus[1]->setValue(0.5 * (lo[1] + hi[1]));
  this->Stylus[2]->setValue(hi[2] + 10);
}

void qRPHapticsPanel::SendStylusPose() {
  if (this->Logic == nullptr) return;
  // The spin boxes are in RAS, as the servo takes the simulated stylus (rpToolInput.h).
  vtkNew<vtkMatrix4x4> stylusToRAS;
  for (int k = 0; k < 3; ++k) stylusToRAS->SetElement(k, 3, this->Stylus[k]->value());
  this->Logic->SetSimulatedStylusPose(stylusToRAS);
}

bool qRPHapticsPanel::Start() {
  if (this->Logic == nullptr) return false;
  if (this->IsRunning()) return true;
  this->RefreshDrives();
  this->FitRangesToHapticModels();
  this->SendStylusPose();  // before the first tick: the loop starts where the spin boxes say
  this->Logic->SetLogPath(this->LogPath->text().trimmed().toStdString());
  std::string error;
  if (!this->Logic->SetDeviceProfile(this->Device->currentData().toString().toStdString(), error)) {
    this->State->setText(QString::fromStdString(error));
    return false;
  }
  // The first haptic scene (BVH over every haptic triangle) is built before the loop starts.
  QApplication::setOverrideCursor(Qt::WaitCursor);
  const bool started = this->Logic->StartSimulated(error);
  QApplication::restoreOverrideCursor();
  if (!started) {
    this->State->setText(QString::fromStdString(error));
    return false;
  }
  this->LogPath->setEnabled(false);
  this->Device->setEnabled(false);
  this->StartButton->setText("Stop");
  this->Timer->start();
  this->Update();
  return true;
}

void qRPHapticsPanel::Stop() {
  this->Timer->stop();
  const bool wasRunning = this->IsRunning();
  if (this->Logic) this->Logic->Stop();  // zero force, join the servo thread, flush the log
  this->StartButton->setText("Start simulated device");
  this->LogPath->setEnabled(true);
  this->Device->setEnabled(true);
  this->State->setText(wasRunning && !this->Logic->GetLogPath().empty()
                           ? "stopped; log " + QString::fromStdString(this->Logic->GetLogPath())
                           : QString("stopped"));
  this->ForceN = 0;
  if (this->Logic) this->Guidance->ShowFixtures(nullptr);
}

void qRPHapticsPanel::Update() {
  if (!this->IsRunning()) return;
  this->Logic->Update();
  // The proxy node appears with the session's first update: the slices follow it from then on.
  if (vtkRPNode* proxy = this->Logic->GetScene()->GetFirstNodeByName(rp::HapticProxyName)) {
    this->FollowProxy->SetFollowNodeID(proxy->GetID());
  }
  this->FollowProxy->Refresh();
  rp::HapticSession* session = this->Logic->GetSession();
  if (session == nullptr) return;
  rp::HapticState s;
  session->Servo().ReadState(s);
  const auto& names = session->TissueNames();
  const bool contact = s.Contacts > 0;
  this->State->setText(QString("running, %1 triangles%2")
                           .arg(session->SceneTriangles())
                           .arg(s.DeviceError ? ", DEVICE ERROR" : (s.Clamped ? ", force clamped" : "")));
  this->Tissue->setText(contact && s.Label >= 0 && static_cast<size_t>(s.Label) < names.size()
                            ? QString::fromStdString(names[static_cast<size_t>(s.Label)])
                            : QString("none"));
  this->ForceN = rp::Norm(s.Force);
  this->Force->setText(QString("%1 N").arg(this->ForceN, 0, 'f', 2));
  this->Penetration->setText(QString("%1 mm").arg(contact ? rp::Norm(s.Hip - s.Proxy) : 0.0, 0, 'f', 2));
  const rp::ServoStats stats = session->Scheduler().Stats();
  this->Timing->setText(
      QString("%1 us / %2 us").arg(stats.Period.P99Us, 0, 'f', 1).arg(stats.Compute.P99Us, 0, 'f', 2));
  this->Missed->setText(QString("%1 of %2 ticks (watchdog trips %3)")
                            .arg(stats.MissedDeadlines)
                            .arg(stats.Ticks)
                            .arg(s.WatchdogTrips));
  // The tissues this device cannot render as the material table asks (they may change when the
  // measured servo period grows).
  QStringList clamped;
  for (const rp::MaterialClamp& c : session->Clamps()) {
    if (c.Clamped())
      clamped << QString("%1: %2 → %3 N/mm").arg(QString::fromStdString(c.Tissue)).arg(c.RequestedStiffness, 0, 'f', 2).arg(c.RenderedStiffness, 0, 'f', 2);
  }
  this->Clamps->setText(clamped.isEmpty() ? QString()
                                          : QString("Clamped to what %1 renders stably (%2 ms servo period):\n")
                                                    .arg(QString::fromStdString(session->DeviceLimits().Name))
                                                    .arg(1e3 * session->StabilityPeriod(), 0, 'f', 2) +
                                                clamped.join("\n"));
  this->Clamps->setVisible(!clamped.isEmpty());
  this->Guidance->ShowFixtures(&s.Fixtures);
}
