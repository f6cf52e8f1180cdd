#ifndef vtkRPToolDisplayableManager_h
#define vtkRPToolDisplayableManager_h
// Tools and other transform nodes with a glyph, drawn in every view (projected in slice views):
//  - vtkRPTrackedToolNode: a stylus by default (tip at the node's origin, shaft along its +Z),
//    dimmed when the tracker does not report it OK; a sphere when the node has a "Force"
//    attribute (the Haptics module's HapticProxy node), with that force as an arrow;
//  - any linear transform node with the attribute "Viewer.Glyph" = stylus | sphere | axes | none.
// Attributes read (all optional):
//  "Viewer.Glyph"        glyph kind (above)
//  "Viewer.GlyphLength"  stylus length / axes length, mm (default 80 / 30)
//  "Viewer.GlyphRadius"  sphere radius (e.g. the haptic proxy), mm (default 2)
//  "Viewer.Color"        "r,g,b" in 0..1
//  "Viewer.Force"        "fx,fy,fz" newtons in RAS: an arrow from the node's origin ("Force" is
//                        used when this is absent)
//  "Viewer.ForceScale"   mm of arrow per newton (default 10)
#include <map>
#include <memory>

#include "vtkRPDisplayableManager.h"

class vtkActor;

class vtkRPToolDisplayableManager : public vtkRPDisplayableManager {
 public:
  static vtkRPToolDisplayableManager* New();
  vtkTypeMacro(vtkRPToolDisplayableManager, vtkRPDisplayableManager);

  /// The glyph and force arrow actors of a node (nullptr when none), for tests.
  vtkActor* GetGlyphActor(vtkRPNode* node) const;
  vtkActor* GetForceActor(vtkRPNode* node) const;

 protected:
  vtkRPToolDisplayableManager() = default;
  ~vtkRPToolDisplayableManager() override;
  bool CanDisplay(vtkRPNode* node) const override;
  void AddDisplay(vtkRPNode* node) override;
  void RemoveDisplay(vtkRPNode* node) override;
  void UpdateDisplay(vtkRPNode* node) override;

 private:
  vtkRPToolDisplayableManager(const vtkRPToolDisplayableManager&) = delete;
  void operator=(const vtkRPToolDisplayableManager&) = delete;
  struct Display;
  std::map<vtkRPNode*, std::unique_ptr<Display>> Displays;
};

#endif
