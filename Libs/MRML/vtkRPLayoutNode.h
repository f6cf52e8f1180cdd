#ifndef vtkRPLayoutNode_h
#define vtkRPLayoutNode_h
// Which views the viewer shows (Slicer's vtkMRMLLayoutNode): the view arrangement, saved with
// the scene so a scene reopens in the layout it was saved in. One singleton per scene.
#include <string>

#include "vtkRPNode.h"

class vtkRPLayoutNode : public vtkRPNode {
 public:
  static vtkRPLayoutNode* New();
  vtkTypeMacro(vtkRPLayoutNode, vtkRPNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Layout"; }
  bool GetHideFromEditors() const override { return true; }

  enum Arrangement { FourUp = 0, OneUp3D, OneUpAxial, OneUpSagittal, OneUpCoronal };
  static const char* GetArrangementAsString(int arrangement);  // "4up", "3d", "axial", "sagittal", "coronal"
  static int GetArrangementFromString(const std::string& text);  // -1 when not recognised

  vtkGetMacro(ViewArrangement, int);
  void SetViewArrangement(int arrangement);  // out-of-range values are ignored

  /// The scene's layout node, added when missing (nullptr for a null scene).
  static vtkRPLayoutNode* GetOrAddLayoutNode(vtkRPScene* scene);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPLayoutNode();
  ~vtkRPLayoutNode() override = default;

 private:
  vtkRPLayoutNode(const vtkRPLayoutNode&) = delete;
  void operator=(const vtkRPLayoutNode&) = delete;
  int ViewArrangement = FourUp;
};

#endif
