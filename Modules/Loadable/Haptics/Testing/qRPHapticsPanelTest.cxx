// The Haptics panel on a flat bone slab: start the simulated device, press the stylus into the
// top face with the spin boxes, and read the force, tissue and penetration back from the panel.
// Known answers: force = k·depth (k of bone from Resources/Materials/materials.json) below the
// device's force limit, and the limit (3.3 N, seed eq. 6) above it; on the Touch (0.4 N/mm) bone
// is clamped to 0.4 N/mm with a warning in the panel.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QPushButton>
#include <QThread>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "qRPHapticsPanel.h"
#include "rpHapticSceneBridge.h"
#include "rpHapticSession.h"
#include "rpSimulatedDevice.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

namespace {
double BoneStiffness() {
  std::ifstream in(std::string(ROBOPLAN_RESOURCES_DIR) + "/Materials/materials.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  for (const auto& m : doc.at("materials"))
    if (m.at("tissue") == "bone") return m.at("stiffness").get<double>();
  return -1;
}
}  // namespace

TEST(HapticsPanel, PressIntoBoneSlabShowsStiffnessForceAndTissue) {
  int argc = 1;
  char name[] = "qRPHapticsPanelTest";
  char* argv[] = {name};
  QApplication app(argc, argv);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPModelNode> slab;  // top face at S = 0
  slab->SetName("Slab");
  slab->SetTissueClass("bone");
  slab->SetHaptic(true);
  slab->SetPolyData(rp::TriangleMeshToPolyData(rp::shapes::Box({-40, -40, -20}, {40, 40, 0})));
  scene->AddNode(slab);
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  const std::string log = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/haptics-panel-session.csv";
  QDir().mkpath(ROBOPLAN_TEST_OUTPUT_DIR);
  std::remove(log.c_str());
  const double k = BoneStiffness();
  ASSERT_GT(k, 0);

  auto panel = std::make_unique<qRPHapticsPanel>(logic.GetPointer());
  panel->LogPathEdit()->setText(QString::fromStdString(log));
  panel->show();
  // Spin box ranges: the haptic models' bounds ± 20 mm.
  EXPECT_DOUBLE_EQ(panel->StylusSpinBox(2)->minimum(), -40);
  EXPECT_DOUBLE_EQ(panel->StylusSpinBox(2)->maximum(), 20);
  auto pump = [&](double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      app.processEvents();
      panel->Update();
      QThread::msleep(10);
    }
  };
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  panel->StylusSpinBox(0)->setValue(3);
  panel->StylusSpinBox(1)->setValue(-4);
  pump(0.6);  // past the 0.5 s force ramp, stylus above the slab
  EXPECT_EQ(panel->TissueText(), "none");
  EXPECT_NEAR(panel->DisplayedForce(), 0, 1e-9);

  // 1 mm into the top face: F = k·1 mm (2 N for bone, under the device limit).
  panel->StylusSpinBox(2)->setValue(-1);
  pump(0.3);
  EXPECT_EQ(panel->TissueText(), "bone");
  EXPECT_NEAR(panel->DisplayedForce(), k * 1.0, 0.15 * k * 1.0) << panel->ForceText().toStdString();
  EXPECT_EQ(panel->PenetrationText(), "1.00 mm");
  std::printf("1 mm into bone: %s (k = %.2f N/mm), servo p99 period / compute %s\n",
              panel->ForceText().toStdString().c_str(), k, panel->TimingText().toStdString().c_str());

  // The default device is the Phantom Omni, which renders bone as the table asks: no warning.
  EXPECT_EQ(panel->DeviceComboBox()->currentData().toString(), "omni");
  EXPECT_FALSE(panel->DeviceComboBox()->isEnabled());  // not while running
  EXPECT_TRUE(panel->ClampText().isEmpty()) << panel->ClampText().toStdString();

  // 5 mm: k·5 mm exceeds the Omni's 3.3 N; the renderer clamps to it (eq. 6).
  panel->StylusSpinBox(2)->setValue(-5);
  pump(0.3);
  EXPECT_EQ(panel->TissueText(), "bone");
  const double limit = rp::SimulatedDevice::DefaultInfo().MaxForce;
  ASSERT_GT(k * 5.0, limit);
  EXPECT_NEAR(panel->DisplayedForce(), limit, 0.05 * limit) << panel->ForceText().toStdString();
  std::printf("5 mm into bone: %s (limit %.1f N)\n", panel->ForceText().toStdString().c_str(), limit);
  EXPECT_TRUE(panel->TimingText().endsWith("us")) << panel->TimingText().toStdString();

  // The Touch renders at most 0.4 N/mm: bone is clamped, the panel says so, 1 mm gives 0.4 N.
  panel->StartStopButton()->click();
  ASSERT_FALSE(panel->IsRunning());
  panel->DeviceComboBox()->setCurrentIndex(panel->DeviceComboBox()->findData("touch"));
  panel->StylusSpinBox(2)->setValue(10);
  panel->StartStopButton()->click();
  ASSERT_TRUE(panel->IsRunning()) << panel->StatusText().toStdString();
  EXPECT_EQ(logic->GetDeviceProfile(), "touch");
  pump(0.6);
  panel->StylusSpinBox(2)->setValue(-1);
  pump(0.3);
  const double touchK = std::min(k, 0.4);
  EXPECT_NEAR(panel->DisplayedForce(), touchK * 1.0, 0.15 * touchK) << panel->ForceText().toStdString();
  if (k > 0.4) {
    EXPECT_NE(panel->ClampText().indexOf("bone: " + QString::number(k, 'f', 2) + " → 0.40 N/mm"), -1)
        << panel->ClampText().toStdString();
    bool warned = false;
    for (const auto& w : logic->GetSession()->Warnings()) warned |= w.rfind("bone: stiffness", 0) == 0;
    EXPECT_TRUE(warned);
  }
  std::printf("Touch, 1 mm into bone: %s; %s\n", panel->ForceText().toStdString().c_str(),
              panel->ClampText().toStdString().c_str());

  // Closing the panel stops the loop and commits the session log.
  panel.reset();
  EXPECT_FALSE(logic->IsRunning());
  double force[3];
  logic->GetLastForce(force);  // the device was left with zero force
  EXPECT_EQ(force[0], 0.0);
  EXPECT_EQ(force[1], 0.0);
  EXPECT_EQ(force[2], 0.0);
  std::ifstream in(log);
  ASSERT_TRUE(in.good()) << log;
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_GT(lines, 500);  // ~1.2 s at 1 kHz
}
