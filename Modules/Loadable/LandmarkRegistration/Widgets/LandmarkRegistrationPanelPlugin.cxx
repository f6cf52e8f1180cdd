// The LandmarkRegistration module's panel plugin (libRoboPlanPanelLandmarkRegistration.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPLandmarkRegistrationPanel.h"
#include "rpModule.h"
#include "vtkRPLandmarkRegistrationLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene* scene, QWidget* parent) {
  return new qRPLandmarkRegistrationPanel(vtkRPLandmarkRegistrationLogic::SafeDownCast(logic), scene, parent);
}
