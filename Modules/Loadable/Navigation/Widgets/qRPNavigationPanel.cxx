#include "qRPNavigationPanel.h"

#include <algorithm>
#include <string>
#include <vector>

#include <QImage>
#include <QPixmap>
#include <QSignalBlocker>
#include <QTimer>

#include "qRPScorePanel.h"
#include "qRPSliceFollowCheckBox.h"
#include "rpSceneNodesWatch.h"
#include "rpTargetView.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPTrajectoryNode.h"

#include <vtkImageData.h>
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"

qRPNavigationPanel::qRPNavigationPanel(vtkRPNavigationLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  this->setupUi(this);
  this->Warning->setValue(logic ? logic->GetWarningDistance() : 3.0);
  this->FollowTool->SetScene(logic ? logic->GetScene() : nullptr);
  this->Score = new qRPScorePanel(logic);
  this->ScoreLayout->addWidget(this->Score);
  this->Picture = std::make_unique<rp::TargetViewPicture>();
  connect(this->Stream, &QCheckBox::toggled, this, &qRPNavigationPanel::ToggleStream);
  connect(this->Volume, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Refreshing) this->Update();
  });
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);  // 30 Hz display rate
  connect(this->Timer, &QTimer::timeout, this, &qRPNavigationPanel::OnTimer);
  connect(this->RefreshButton, &QPushButton::clicked, this, &qRPNavigationPanel::RefreshNodeLists);
  connect(this->Tool, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Refreshing) this->Update();
  });
  connect(this->Trajectory, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (this->Refreshing) return;
    this->Update();
    const int scored = this->Score->TrajectoryCombo->findData(this->Trajectory->currentData());
    if (scored >= 0 && !this->Trajectory->currentData().toString().isEmpty()) this->Score->TrajectoryCombo->setCurrentIndex(scored);
  });
  connect(this->Models, &QListWidget::itemChanged, this, [this](QListWidgetItem*) {
    if (!this->Refreshing) this->Update();
  });
  connect(this->Warning, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this, [this](double) { this->Update(); });
  this->SceneWatch = std::make_unique<rp::SceneNodesWatch>(logic ? logic->GetScene() : nullptr);
  this->RefreshNodeLists();
  this->Timer->start();
}

void qRPNavigationPanel::OnTimer() {
  if (this->SceneWatch->TakeChanged()) {
    this->RefreshNodeLists();  // also updates
  } else {
    this->Update();
  }
  this->FollowTool->Refresh();
}

qRPNavigationPanel::~qRPNavigationPanel() {
  this->Timer->stop();
  if (this->Logic) this->Logic->SetToolNodeID("");  // stop observing the tool
}

QString qRPNavigationPanel::DistanceText() const { return this->Distance->text(); }
QString qRPNavigationPanel::ClosestModelText() const { return this->Closest->text(); }
QString qRPNavigationPanel::ReadoutText() const { return this->Readout->text(); }
QString qRPNavigationPanel::StructureText() const { return this->Structure->text(); }
QString qRPNavigationPanel::StreamText() const { return this->StreamState->text(); }
QImage qRPNavigationPanel::TargetViewImage() const { return this->TargetPicture->pixmap(Qt::ReturnByValue).toImage(); }

void qRPNavigationPanel::ToggleStream(bool on) {
  if (!this->Logic) return;
  if (!on) {
    this->Logic->StopReadoutServer();
    this->StreamState->setText("not streaming");
    return;
  }
  std::string error;
  if (!this->Logic->StartReadoutServer(this->StreamPort->value(), error)) {
    this->StreamState->setText(QString::fromStdString(error));
    const QSignalBlocker block(this->Stream);
    this->Stream->setChecked(false);
  }
}

void qRPNavigationPanel::ShowTargetView() {
  const rp::GuidanceReadout& g = this->Logic->GetLastReadout();
  auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(this->Logic->GetScene()->GetNodeByID(this->Logic->GetTrajectoryNodeID()));
  auto* volume = vtkRPScalarVolumeNode::SafeDownCast(
      this->Logic->GetScene()->GetNodeByID(this->Volume->currentData().toString().toStdString()));
  double entry[3], target[3];
  rp::TrajectoryAxis plan;
  std::string error;
  if (!g.Valid || !trajectory || !trajectory->GetEntryWorld(entry) || !trajectory->GetTargetWorld(target) ||
      !rp::TrajectoryAxis::Make({entry[0], entry[1], entry[2]}, {target[0], target[1], target[2]}, plan, error)) {
    this->TargetPicture->clear();
    this->PictureShown.clear();
    return;
  }
  // Redraw only when what it shows changed (a still tool costs nothing at display rate).
  std::vector<double> shown(g.ToolTipToTrajectory, g.ToolTipToTrajectory + 16);
  shown.insert(shown.end(), {entry[0], entry[1], entry[2], target[0], target[1], target[2],
                             volume ? static_cast<double>(volume->GetMTime()) : -1.0});
  if (shown == this->PictureShown) return;
  this->PictureShown = shown;
  if (!this->Picture->Render(plan, g, volume, error)) {
    this->TargetPicture->setText(QString::fromStdString(error));
    return;
  }
  vtkImageData* image = this->Picture->GetImage();
  int dims[3];
  image->GetDimensions(dims);
  const auto* rgb = static_cast<const uchar*>(image->GetScalarPointer());
  QImage picture(rgb, dims[0], dims[1], 3 * dims[0], QImage::Format_RGB888);
  this->TargetPicture->setPixmap(QPixmap::fromImage(picture.mirrored()));  // VTK's rows start at the bottom
}

void qRPNavigationPanel::showEvent(QShowEvent* event) {
  this->RefreshNodeLists();
  QWidget::showEvent(event);
}

void qRPNavigationPanel::RefreshNodeLists() {
  vtkRPScene* scene = this->Logic ? this->Logic->GetScene() : nullptr;
  if (scene == nullptr) return;
  this->Refreshing = true;
  const QString tool = this->Tool->currentData().toString();
  this->Tool->clear();
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPLinearTransformNode"))
    this->Tool->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  int index = this->Tool->findData(tool);
  // No earlier choice: prefer a tip node (the stylus tip, then the haptic proxy).
  if (index < 0) index = this->Tool->findText("StylusTipToStylus");
  if (index < 0) index = this->Tool->findText("HapticProxy");
  this->Tool->setCurrentIndex(index >= 0 ? index : 0);
  const QString trajectory = this->Trajectory->currentData().toString();
  this->Trajectory->clear();
  this->Trajectory->addItem("(none)", QString());
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPTrajectoryNode"))
    this->Trajectory->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  this->Trajectory->setCurrentIndex(std::max(0, this->Trajectory->findData(trajectory)));
  const QString volume = this->Volume->currentData().toString();
  const bool hadVolumes = this->Volume->count() > 1;  // none before: show the first one that came
  this->Volume->clear();
  this->Volume->addItem("(none)", QString());
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPScalarVolumeNode"))
    this->Volume->addItem(QString::fromStdString(node->GetName()), QString::fromStdString(node->GetID()));
  const int volumeIndex = hadVolumes ? this->Volume->findData(volume) : -1;
  this->Volume->setCurrentIndex(volumeIndex >= 0 ? volumeIndex : std::min(1, this->Volume->count() - 1));

  QStringList checked;
  for (int i = 0; i < this->Models->count(); ++i)
    if (this->Models->item(i)->checkState() == Qt::Checked) checked << this->Models->item(i)->data(Qt::UserRole).toString();
  this->Score->RefreshNodeLists();
  this->Models->clear();
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPModelNode")) {
    auto* item = new QListWidgetItem(QString::fromStdString(node->GetName()), this->Models);
    const QString id = QString::fromStdString(node->GetID());
    item->setData(Qt::UserRole, id);
    item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
    item->setCheckState(checked.contains(id) ? Qt::Checked : Qt::Unchecked);
  }
  this->Refreshing = false;
  this->Update();
}

void qRPNavigationPanel::ApplySettings() {
  const std::string tool = this->Tool->currentData().toString().toStdString();
  if (tool != this->Logic->GetToolNodeID()) this->Logic->SetToolNodeID(tool);
  this->FollowTool->SetFollowNodeID(tool);
  const std::string trajectory = this->Trajectory->currentData().toString().toStdString();
  if (trajectory != this->Logic->GetTrajectoryNodeID()) this->Logic->SetTrajectoryNodeID(trajectory);
  std::vector<std::string> models;
  for (int i = 0; i < this->Models->count(); ++i)
    if (this->Models->item(i)->checkState() == Qt::Checked)
      models.push_back(this->Models->item(i)->data(Qt::UserRole).toString().toStdString());
  this->Logic->SetTargetModelNodeIDs(models);
  if (this->Warning->value() != this->Logic->GetWarningDistance()) this->Logic->SetWarningDistance(this->Warning->value());
}

void qRPNavigationPanel::ShowReadout() {
  const rp::GuidanceReadout& g = this->Logic->GetLastReadout();
  this->StructureWarningShown = g.Valid && g.HasStructure && g.WithinMargin;
  this->Structure->setStyleSheet(this->StructureWarningShown ? "color: rgb(220, 30, 30);" : "");
  if (!g.Valid) {
    this->Readout->setText("-");
    this->Structure->setText("-");
    return;
  }
  this->Structure->setText(g.HasStructure ? QString("closest structure at risk: %1 %2 mm%3")
                                                .arg(QString::fromStdString(g.ClosestStructure))
                                                .arg(g.ClosestStructureMm, 0, 'f', 1)
                                                .arg(g.WithinMargin ? " (within its margin)" : "")
                                          : QString::fromStdString(this->Logic->GetStructuresProblem().empty()
                                                                       ? std::string("no structure at risk in the scene")
                                                                       : this->Logic->GetStructuresProblem()));
  this->Readout->setText(QString::fromUtf8("entry %1 mm · angle %2° · depth to target %3 mm · lateral %4 mm")
                             .arg(g.EntryErrorMm, 0, 'f', 1)
                             .arg(g.AngleDeg, 0, 'f', 1)
                             .arg(g.DepthToTargetMm, 0, 'f', 1)
                             .arg(g.LateralMm, 0, 'f', 1));
}

void qRPNavigationPanel::Update() {
  if (this->Logic == nullptr || this->Logic->GetScene() == nullptr) return;
  this->ApplySettings();
  const vtkRPNavigationLogic::Result r = this->Logic->Update();
  this->ShowReadout();
  this->ShowTargetView();
  if (this->Logic->GetReadoutServerPort() > 0)
    this->StreamState->setText(QString("streaming on 127.0.0.1:%1, %2 client(s)")
                                   .arg(this->Logic->GetReadoutServerPort())
                                   .arg(this->Logic->GetReadoutClientCount()));
  if (!r.Valid) {
    this->Distance->setText("-");
    this->Distance->setStyleSheet("");
    this->Closest->setText(this->Tool->count() == 0 ? "no transform node in the scene" : "choose the models to measure to");
    this->WarningShown = false;
    return;
  }
  this->WarningShown = r.Warning;
  this->Distance->setText(QString("%1 mm").arg(r.DistanceMM, 0, 'f', 1));
  this->Distance->setStyleSheet(r.Warning ? "color: rgb(220, 30, 30);" : "color: rgb(20, 160, 60);");
  vtkRPNode* model = this->Logic->GetScene()->GetNodeByID(r.ClosestModelID);
  this->Closest->setText(QString("closest: %1%2")
                             .arg(model ? QString::fromStdString(model->GetName()) : QString::fromStdString(r.ClosestModelID))
                             .arg(r.DistanceMM < 0 ? " (tip inside)" : ""));
}
