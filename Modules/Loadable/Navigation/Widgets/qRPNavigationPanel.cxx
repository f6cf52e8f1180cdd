#include "qRPNavigationPanel.h"

#include <algorithm>
#include <string>
#include <vector>

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QTimer>
#include <QVBoxLayout>


#include "qRPSliceFollowCheckBox.h"
#include "rpSceneNodesWatch.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPNavigationLogic.h"
#include "vtkRPScene.h"

qRPNavigationPanel::qRPNavigationPanel(vtkRPNavigationLogic* logic, QWidget* parent) : QWidget(parent), Logic(logic) {
  auto* form = new QFormLayout;
  this->Tool = new QComboBox;
  this->Tool->setToolTip("A transform node whose origin is the tool tip (e.g. StylusTipToStylus, HapticProxy)");
  this->Warning = new QDoubleSpinBox;
  this->Warning->setRange(0, 100);
  this->Warning->setDecimals(1);
  this->Warning->setSuffix(" mm");
  this->Warning->setValue(logic ? logic->GetWarningDistance() : 3.0);
  auto* refresh = new QPushButton("Refresh node lists");
  this->Trajectory = new QComboBox;
  this->Trajectory->setToolTip("A planned trajectory: the tool is read out against it (the tool points along its -z)");
  form->addRow("Tool (tip at origin)", this->Tool);
  form->addRow("Planned trajectory", this->Trajectory);
  form->addRow("Warning distance", this->Warning);
  this->FollowTool = new qRPSliceFollowCheckBox("Slices follow the tool");
  this->FollowTool->SetScene(logic ? logic->GetScene() : nullptr);
  form->addRow(this->FollowTool);
  this->Models = new QListWidget;
  this->Distance = new QLabel("-");
  QFont big = this->Distance->font();
  big.setPointSize(28);
  big.setBold(true);
  this->Distance->setFont(big);
  this->Distance->setAlignment(Qt::AlignCenter);
  this->Closest = new QLabel("-");
  this->Closest->setAlignment(Qt::AlignCenter);
  this->Readout = new QLabel("-");
  this->Readout->setAlignment(Qt::AlignCenter);
  this->Structure = new QLabel("-");
  this->Structure->setAlignment(Qt::AlignCenter);
  this->Structure->setToolTip("The scene's structures at risk (protected models and segments), from the tool's surface");
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addWidget(new QLabel("Measure to the models:"));
  layout->addWidget(this->Models, 1);
  layout->addWidget(refresh);
  layout->addWidget(this->Distance);
  layout->addWidget(this->Closest);
  layout->addWidget(this->Readout);
  layout->addWidget(this->Structure);
  this->Timer = new QTimer(this);
  this->Timer->setInterval(33);  // 30 Hz display rate
  connect(this->Timer, &QTimer::timeout, this, &qRPNavigationPanel::OnTimer);
  connect(refresh, &QPushButton::clicked, this, &qRPNavigationPanel::RefreshNodeLists);
  connect(this->Tool, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Refreshing) this->Update();
  });
  connect(this->Trajectory, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Refreshing) this->Update();
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

  QStringList checked;
  for (int i = 0; i < this->Models->count(); ++i)
    if (this->Models->item(i)->checkState() == Qt::Checked) checked << this->Models->item(i)->data(Qt::UserRole).toString();
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
