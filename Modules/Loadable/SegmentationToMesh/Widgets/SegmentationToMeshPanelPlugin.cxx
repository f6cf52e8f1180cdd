// The SegmentationToMesh module's panel plugin (libRoboPlanPanelSegmentationToMesh.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include <QScrollArea>

#include "qRPSegmentationToMeshPanel.h"
#include "rpModule.h"
#include "vtkRPSegmentationToMeshLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  auto* segmentationLogic = vtkRPSegmentationToMeshLogic::SafeDownCast(logic);
  if (!segmentationLogic || !segmentationLogic->GetScene()) return nullptr;
  // The panel is taller than a module page on a laptop screen: let it scroll.
  auto* scroll = new QScrollArea(parent);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setWidget(new qRPSegmentationToMeshPanel(segmentationLogic));
  return scroll;
}
