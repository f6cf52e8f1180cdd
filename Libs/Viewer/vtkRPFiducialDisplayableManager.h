#ifndef vtkRPFiducialDisplayableManager_h
#define vtkRPFiducialDisplayableManager_h
// Control points of every markups node (fiducial lists, a trajectory's entry and target, a cut
// plane's origin): a sphere per visible point, with its label, in the node's colour.
// In a slice view only points within half a slice step of the plane are drawn. Labels are
// screen text drawn over everything, laid out each time the view renders so that none
// overprints another (rp::PlaceLabels) and all stay inside the view.
#include <map>
#include <memory>

#include <vtkNew.h>

#include "vtkRPDisplayableManager.h"

class vtkCallbackCommand;
class vtkRenderer;

class vtkRPFiducialDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPFiducialDisplayableManager* New();
  vtkTypeMacro(vtkRPFiducialDisplayableManager, vtkRPDisplayableManager);

  /// Number of points of a list drawn now (tests use it).
  int GetNumberOfDrawnPoints(vtkRPNode* node) const;
  /// Sphere radius in mm (default 2).
  void SetGlyphRadius(double radius);

 protected:
  vtkRPFiducialDisplayableManager();
  ~vtkRPFiducialDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;
  void OnInitialize() override;
  void OnFinalize() override;

 private:
  vtkRPFiducialDisplayableManager(const vtkRPFiducialDisplayableManager&) = delete;
  void operator=(const vtkRPFiducialDisplayableManager&) = delete;
  struct Display;
  void LayOutLabels();
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
  vtkNew<vtkCallbackCommand> LayoutCallback;
  vtkRenderer* LayoutRenderer = nullptr;
  unsigned long LayoutTag = 0;
  double GlyphRadius = 2.0;
};

#endif
