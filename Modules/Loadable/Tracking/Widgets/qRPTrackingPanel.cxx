#include "qRPTrackingPanel.h"

#include <QHeaderView>
#include <QSocketNotifier>
#include <QTimer>

#include "rpPivotCalibration.h"
#include "rpPoseSource.h"
#include "rpResources.h"
#include "rpTransformNames.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

qRPTrackingPanel::qRPTrackingPanel(vtkRPTrackingLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  for (const auto& entry : rp::PoseSourceRegistry::Entries())
    this->Kind->addItem(QString::fromStdString(entry.Description), QString::fromStdString(entry.Kind));
  this->Kind->setCurrentIndex(std::max(0, this->Kind->findData("simulator")));
  const QString tools = QString::fromStdString(rp::ResourcePath("Tools")) + "/";
  this->Tools->setText(tools + "Stylus.json;" + tools + "Reference.json");
  this->Table->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);  // not a Designer property
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);
  this->Coalesce = new QTimer(this);
  this->Coalesce->setSingleShot(true);
  connect(this->Timer, &QTimer::timeout, this, &qRPTrackingPanel::Update);
  connect(this->Coalesce, &QTimer::timeout, this, &qRPTrackingPanel::Update);
  connect(this->ConnectButton, &QPushButton::clicked, this, &qRPTrackingPanel::OnConnectClicked);
  connect(this->PivotButton, &QPushButton::clicked, this, [this] { this->StartPivotCalibration(10); });
  connect(this->Kind, QOverload<int>::of(&QComboBox::currentIndexChanged), this, &qRPTrackingPanel::ShowAddressHint);
  this->ShowAddressHint();
}

qRPTrackingPanel::~qRPTrackingPanel() { this->Disconnect(); }

QString qRPTrackingPanel::StatusText() const { return this->State->text(); }
QString qRPTrackingPanel::PivotText() const { return this->Pivot->text(); }
bool qRPTrackingPanel::IsConnected() const { return this->SourceId >= 0; }
rp::PoseSource* qRPTrackingPanel::Source() const { return this->Logic->GetSource(this->SourceId); }

void qRPTrackingPanel::ShowAddressHint() {
  const std::string kind = this->Kind->currentData().toString().toStdString();
  for (const auto& entry : rp::PoseSourceRegistry::Entries())
    if (entry.Kind == kind) this->Address->setPlaceholderText(QString::fromStdString(entry.AddressHint));
}

void qRPTrackingPanel::OnConnectClicked() {
  if (this->IsConnected()) {
    this->Disconnect();
    return;
  }
  this->ConnectSource(this->Kind->currentData().toString(), this->Address->text(),
                      this->Tools->text().split(';', Qt::SkipEmptyParts));
}

bool qRPTrackingPanel::ConnectSource(const QString& kind, const QString& address, const QStringList& toolFiles) {
  this->Disconnect();
  rp::PoseSourceConfig config;
  config.Kind = kind.toStdString();
  config.Address = address.trimmed().toStdString();
  for (const QString& file : toolFiles) config.ToolFiles.push_back(file.trimmed().toStdString());
  std::string error;
  this->SourceId = this->Logic->Connect(config, error);
  if (this->SourceId < 0) {
    this->State->setText(QString("error: ") + QString::fromStdString(error));
    return false;
  }
  for (int fd : this->Logic->GetReadyFds()) {
    auto* notifier = new QSocketNotifier(fd, QSocketNotifier::Read, this);
    connect(notifier, &QSocketNotifier::activated, this, &qRPTrackingPanel::OnSourceReady);
    this->Notifiers.push_back(notifier);
  }
  this->ConnectButton->setText("Disconnect");
  this->Timer->start();
  this->Update();
  return true;
}

void qRPTrackingPanel::Disconnect() {
  this->Timer->stop();
  this->Coalesce->stop();
  for (QSocketNotifier* notifier : this->Notifiers) delete notifier;  // before the source closes its fd
  this->Notifiers.clear();
  if (this->SourceId >= 0) this->Logic->RemoveSource(this->SourceId);  // stops the device (TSTOP ...)
  this->SourceId = -1;
  this->PivotEnd = 0;
  this->ConnectButton->setText("Connect");
  this->State->setText("not connected");
}

void qRPTrackingPanel::OnSourceReady() {
  // New data: into the scene now, unless the last update was less than MinUpdateMs ago.
  const double wait = this->LastUpdate + MinUpdateMs * 1e-3 - rp::SteadySeconds();
  if (wait <= 0) {
    this->Update();
  } else {
    if (rp::PoseSource* source = this->Source()) source->DrainReady();  // the timer will look
    if (!this->Coalesce->isActive()) this->Coalesce->start(static_cast<int>(wait * 1e3) + 1);
  }
}

void qRPTrackingPanel::StartPivotCalibration(double seconds, const QString& toolNodeName) {
  this->PivotPoses.clear();
  this->PivotTool = toolNodeName.isEmpty() ? rp::ToolToTrackerName("Stylus") : toolNodeName.toStdString();
  this->PivotEnd = rp::SteadySeconds() + seconds;
  this->PivotLastCount = 0;
  this->Pivot->setText("pivot the stylus about its tip...");
}

void qRPTrackingPanel::Update() {
  rp::PoseSource* source = this->Source();
  if (!source) return;
  const double now = rp::SteadySeconds();
  this->LastUpdate = now;
  this->Logic->UpdateNodes(now);
  this->State->setText(QString::fromStdString(source->StatusText()));
  const auto stats = this->Logic->GetToolStatistics();
  this->Table->setRowCount(static_cast<int>(stats.size()));
  for (int row = 0; row < static_cast<int>(stats.size()); ++row) {
    const auto& s = stats[static_cast<size_t>(row)];
    const QStringList cells = {QString::fromStdString(s.NodeName), vtkRPTrackedToolNode::GetStatusAsString(s.Status),
                               QString::number(s.RateHz, 'f', 1), QString::number(s.Frames.Ok),
                               QString::number(s.Frames.Missing), QString::number(s.Frames.OutOfVolume),
                               s.ErrorRMS >= 0 ? QString::number(s.ErrorRMS, 'f', 3) : "-"};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = this->Table->item(row, c);
      if (!item) this->Table->setItem(row, c, item = new QTableWidgetItem);
      item->setText(cells[c]);
    }
    this->Table->item(row, 1)->setForeground(s.Status == vtkRPTrackedToolNode::StatusOK ? Qt::darkGreen : Qt::red);
  }
  // Pivot: every fresh stylus pose (newest-only is enough for a slow pivoting motion).
  if (this->PivotEnd > 0) {
    const rp::ToolPoseTable& table = source->Poses();
    const int slot = table.Find(this->PivotTool.c_str(), this->PivotTool.size());
    rp::ToolPose pose;
    const uint64_t n = slot >= 0 ? table.Read(slot, pose) : 0;
    if (n > this->PivotLastCount) {
      this->PivotLastCount = n;
      this->PivotPoses.push_back(pose);
    }
    if (now >= this->PivotEnd) {
      this->PivotEnd = 0;
      const rp::PivotResult r = this->Logic->CalibratePivot(this->PivotPoses, this->PivotTool);
      this->Pivot->setText(r.Valid ? QString("tip %1 %2 %3 mm, RMSE %4 mm: %5")
                                         .arg(r.TipOffset[0], 0, 'f', 2)
                                         .arg(r.TipOffset[1], 0, 'f', 2)
                                         .arg(r.TipOffset[2], 0, 'f', 2)
                                         .arg(r.Rmse, 0, 'f', 3)
                                         .arg(r.Accepted ? "accepted" : "REJECTED")
                                   : QString::fromStdString(r.Message));
    }
  }
}
