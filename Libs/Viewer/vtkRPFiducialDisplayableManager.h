#ifndef vtkRPFiducialDisplayableManager_h
#define vtkRPFiducialDisplayableManager_h
// Fiducial lists: a sphere per visible control point, with its label, in the list's colour
// (selected points brighter). In a slice view only points within half a slice step of the
// plane are drawn.
#include <map>
#include <memory>

#include "vtkRPDisplayableManager.h"

class vtkRPFiducialDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPFiducialDisplayableManager* New();
  vtkTypeMacro(vtkRPFiducialDisplayableManager, vtkRPDisplayableManager);

  /// Number of points of a list drawn now (tests use it).
  int GetNumberOfDrawnPoints(vtkRPNode* node) const;
  /// Sphere radius in mm (default 2).
  void SetGlyphRadius(double radius);

 protected:
  vtkRPFiducialDisplayableManager() = default;
  ~vtkRPFiducialDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;
  void OnViewStateModified() override;

 private:
  vtkRPFiducialDisplayableManager(const vtkRPFiducialDisplayableManager&) = delete;
  void operator=(const vtkRPFiducialDisplayableManager&) = delete;
  struct Display;
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
  double GlyphRadius = 2.0;
};

#endif
