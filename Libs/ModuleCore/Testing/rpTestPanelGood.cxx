// The TestGood module's panel plugin for the loader tests: no Qt; it hands back the parent it got
// when the module's logic and the scene reached it, so a test can see the arguments went through.
#include "rpModule.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene* scene, QWidget* parent) {
  return logic == nullptr && scene != nullptr ? parent : nullptr;
}
