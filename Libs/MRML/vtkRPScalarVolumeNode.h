#ifndef vtkRPScalarVolumeNode_h
#define vtkRPScalarVolumeNode_h
// A scalar volume (CT in HU, MR intensity): image + IJK-to-RAS + display window/level.
#include "vtkRPImageNode.h"

class vtkRPScalarVolumeNode : public vtkRPImageNode {
 public:
  static vtkRPScalarVolumeNode* New();
  vtkTypeMacro(vtkRPScalarVolumeNode, vtkRPImageNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Volume"; }

  vtkGetMacro(Window, double);
  vtkSetMacro(Window, double);
  vtkGetMacro(Level, double);
  vtkSetMacro(Level, double);
  void SetWindowLevel(double window, double level);
  /// Window/level covering the image's scalar range (used when nothing better is known).
  void SetWindowLevelFromScalarRange();

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPScalarVolumeNode() = default;
  ~vtkRPScalarVolumeNode() override = default;

 private:
  vtkRPScalarVolumeNode(const vtkRPScalarVolumeNode&) = delete;
  void operator=(const vtkRPScalarVolumeNode&) = delete;
  double Window = 400.0;
  double Level = 40.0;
};

#endif
