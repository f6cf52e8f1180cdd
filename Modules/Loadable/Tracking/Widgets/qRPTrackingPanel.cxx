#include "qRPTrackingPanel.h"

#include <QComboBox>
#include <QDir>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>

#include "rpIgtlClient.h"
#include "rpNdiTracker.h"
#include "rpPivotCalibration.h"
#include "rpPolarisSimulator.h"
#include "rpToolDefinition.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

#ifndef ROBOPLAN_RESOURCES_DIR
#define ROBOPLAN_RESOURCES_DIR ""
#endif

qRPTrackingPanel::qRPTrackingPanel(vtkRPTrackingLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  auto* form = new QFormLayout;
  this->Source = new QComboBox;
  this->Source->addItems({"NDI serial", "OpenIGTLink", "Polaris simulator"});
  this->Source->setCurrentIndex(Simulator);
  this->Address = new QLineEdit;
  this->Address->setPlaceholderText("/dev/ttyUSB0  or  127.0.0.1:18944");
  const QString tools = QString(ROBOPLAN_RESOURCES_DIR) + "/Tools/";
  this->Tools = new QLineEdit(tools + "Stylus.json;" + tools + "Reference.json");
  this->ConnectButton = new QPushButton("Connect");
  this->State = new QLabel("not connected");
  form->addRow("Source", this->Source);
  form->addRow("Port / address", this->Address);
  form->addRow("Tool definitions", this->Tools);
  form->addRow(this->ConnectButton, this->State);
  this->Table = new QTableWidget(0, 5);
  this->Table->setHorizontalHeaderLabels({"Tool", "Status", "Rate (Hz)", "Dropped", "Error (mm)"});
  this->Table->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
  this->Table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  this->PivotButton = new QPushButton("Pivot calibration (10 s)");
  this->Pivot = new QLabel;
  auto* pivotRow = new QHBoxLayout;
  pivotRow->addWidget(this->PivotButton);
  pivotRow->addWidget(this->Pivot, 1);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addWidget(this->Table, 1);
  layout->addLayout(pivotRow);
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);
  connect(this->Timer, &QTimer::timeout, this, &qRPTrackingPanel::Update);
  connect(this->ConnectButton, &QPushButton::clicked, this, &qRPTrackingPanel::OnConnectClicked);
  connect(this->PivotButton, &QPushButton::clicked, this, [this] { this->StartPivotCalibration(10); });
}

qRPTrackingPanel::~qRPTrackingPanel() { this->Disconnect(); }

QString qRPTrackingPanel::StatusText() const { return this->State->text(); }
QString qRPTrackingPanel::PivotText() const { return this->Pivot->text(); }
bool qRPTrackingPanel::IsConnected() const { return this->SourceId >= 0; }

const rp::ToolPoseTable* qRPTrackingPanel::Poses() const {
  if (this->Tracker) return &this->Tracker->Poses();
  if (this->Client) return &this->Client->Poses();
  return nullptr;
}

void qRPTrackingPanel::OnConnectClicked() {
  if (this->IsConnected()) {
    this->Disconnect();
    return;
  }
  this->ConnectSource(static_cast<SourceKind>(this->Source->currentIndex()), this->Address->text(),
                      this->Tools->text().split(';', Qt::SkipEmptyParts));
}

bool qRPTrackingPanel::ConnectSource(SourceKind kind, const QString& address, const QStringList& toolFiles) {
  this->Disconnect();
  try {
    if (kind == OpenIGTLink) {
      rp::IgtlClient::Options o;
      const int colon = address.lastIndexOf(':');
      bool ok = colon > 0;
      o.Host = address.left(colon).toStdString();
      o.Port = address.mid(colon + 1).toInt(&ok);
      if (!ok) throw std::runtime_error("address must be HOST:PORT");
      this->Client = std::make_unique<rp::IgtlClient>(o);
      this->Client->Start();
      this->SourceId = this->Logic->AddPoseSource(&this->Client->Poses());
    } else {
      rp::NdiTracker::Options o;
      o.Port = address.toStdString();
      std::vector<rp::ToolDefinition> definitions;
      for (const QString& file : toolFiles) {
        if (QFileInfo(file).suffix() == "json") {
          definitions.push_back(rp::ReadToolDefinition(file.toStdString()));
          o.Tools.push_back({definitions.back().Name, definitions.back().Rom});
        } else {
          o.Tools.push_back({QFileInfo(file).completeBaseName().toStdString(), rp::ReadBinaryFile(file.toStdString())});
        }
      }
      if (o.Tools.empty()) throw std::runtime_error("give at least one tool definition");
      if (kind == Simulator) {
        rp::PolarisSimulator::Options so;
        so.NoiseMm = 0.05;
        this->Sim = std::make_unique<rp::PolarisSimulator>(so);
        for (const auto& d : definitions) this->Sim->AddTool(d);
        std::string error;
        if (!this->Sim->Start(error)) throw std::runtime_error(error);
        o.Port = this->Sim->PortPath();
      }
      if (o.Port.empty()) throw std::runtime_error("give the serial port");
      this->Tracker = std::make_unique<rp::NdiTracker>(o);
      this->Tracker->Start();
      this->SourceId = this->Logic->AddPoseSource(&this->Tracker->Poses());
    }
  } catch (const std::exception& e) {
    this->Disconnect();
    this->State->setText(QString("error: ") + e.what());
    return false;
  }
  this->ConnectButton->setText("Disconnect");
  this->Timer->start();
  this->Update();
  return true;
}

void qRPTrackingPanel::Disconnect() {
  this->Timer->stop();
  if (this->SourceId >= 0) this->Logic->RemovePoseSource(this->SourceId);
  this->SourceId = -1;
  this->Tracker.reset();  // stops its thread (TSTOP) before the simulator goes
  this->Client.reset();
  this->Sim.reset();
  this->PivotEnd = 0;
  this->ConnectButton->setText("Connect");
  this->State->setText("not connected");
}

void qRPTrackingPanel::StartPivotCalibration(double seconds, const QString& toolNodeName) {
  this->PivotPoses.clear();
  this->PivotTool = toolNodeName.toStdString();
  this->PivotEnd = rp::SteadySeconds() + seconds;
  this->PivotLastCount = 0;
  this->Pivot->setText("pivot the stylus about its tip...");
}

void qRPTrackingPanel::Update() {
  if (!this->IsConnected()) return;
  const double now = rp::SteadySeconds();
  this->Logic->UpdateNodes(now);
  if (this->Tracker) {
    const QString error = QString::fromStdString(this->Tracker->LastError());
    this->State->setText(QString(rp::NdiTracker::StateName(this->Tracker->GetState())) + (error.isEmpty() ? "" : ": " + error));
  } else if (this->Client) {
    this->State->setText(this->Client->Connected() ? "connected" : "connecting: " + QString::fromStdString(this->Client->LastError()));
  }
  const auto stats = this->Logic->GetToolStatistics();
  this->Table->setRowCount(static_cast<int>(stats.size()));
  for (int row = 0; row < static_cast<int>(stats.size()); ++row) {
    const auto& s = stats[static_cast<size_t>(row)];
    const QStringList cells = {QString::fromStdString(s.NodeName), vtkRPTrackedToolNode::GetStatusAsString(s.Status),
                               QString::number(s.RateHz, 'f', 1), QString::number(s.Dropped),
                               s.ErrorRMS >= 0 ? QString::number(s.ErrorRMS, 'f', 3) : "-"};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = this->Table->item(row, c);
      if (!item) this->Table->setItem(row, c, item = new QTableWidgetItem);
      item->setText(cells[c]);
    }
    this->Table->item(row, 1)->setForeground(s.Status == vtkRPTrackedToolNode::StatusOK ? Qt::darkGreen : Qt::red);
  }
  // Pivot: every fresh stylus pose (read straight from the table, newest-only is enough at 30 Hz
  // for a slow pivoting motion).
  if (this->PivotEnd > 0) {
    const rp::ToolPoseTable* table = this->Poses();
    for (int i = 0; table && i < table->Count(); ++i) {
      if (this->PivotTool != table->Name(i)) continue;
      rp::ToolPose pose;
      const uint64_t n = table->Read(i, pose);
      if (n > this->PivotLastCount) {
        this->PivotLastCount = n;
        this->PivotPoses.push_back(pose);
      }
    }
    if (now >= this->PivotEnd) {
      this->PivotEnd = 0;
      const rp::PivotResult r = rp::PivotCalibrate(this->PivotPoses, 1.0);
      if (r.Valid) this->Logic->ApplyPivotCalibration(r, this->PivotTool);
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
