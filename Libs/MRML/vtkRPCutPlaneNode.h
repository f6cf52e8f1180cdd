#ifndef vtkRPCutPlaneNode_h
#define vtkRPCutPlaneNode_h
// A planned cut: Slicer's markups plane ("MarkupsPlane", point-normal type): its one control
// point is the origin; the normal and an in-plane x axis (kept orthonormal; y = normal x x) give
// its orientation, `Size` (mm along x and y) the rectangle drawn, centred on the origin. The
// figures of a cut use the whole plane, not the rectangle.
#include "vtkRPPlanNode.h"

class vtkRPCutPlaneNode : public vtkRPPlanNode {
 public:
  static vtkRPCutPlaneNode* New();
  vtkTypeMacro(vtkRPCutPlaneNode, vtkRPPlanNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "CutPlane"; }
  const char* GetMarkupsType() const override { return "Plane"; }
  int GetMaximumNumberOfControlPoints() const override { return 1; }

  bool IsComplete() const { return this->GetNumberOfControlPoints() == 1; }
  /// Places (or moves) the origin. False when locked.
  bool SetOrigin(const double originRAS[3]);
  bool GetOrigin(double originRAS[3]) const;
  bool GetOriginWorld(double originWorld[3]) const;
  /// Sets the normal (normalised). False, and nothing changed, for a zero or non-finite vector.
  /// The x axis is turned with it (the smallest rotation), staying in the plane.
  bool SetNormal(const double normal[3]);
  void GetNormal(double normal[3]) const;
  /// In-plane x axis: projected onto the plane and normalised; false (nothing changed) when it is
  /// (nearly) along the normal or not finite.
  bool SetXAxis(const double xAxis[3]);
  void GetXAxis(double xAxis[3]) const;
  void GetYAxis(double yAxis[3]) const;
  /// The axes with the parent transforms applied (the normal by the inverse transpose), unit.
  void GetNormalWorld(double normal[3]) const;
  void GetXAxisWorld(double xAxis[3]) const;
  /// Rectangle drawn, mm (each > 0; others ignored).
  void SetSize(double x, double y);
  const double* GetSize() const { return this->Size; }

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPCutPlaneNode();
  ~vtkRPCutPlaneNode() override = default;

 private:
  vtkRPCutPlaneNode(const vtkRPCutPlaneNode&) = delete;
  void operator=(const vtkRPCutPlaneNode&) = delete;
  double Normal[3] = {0, 0, 1};
  double XAxis[3] = {1, 0, 0};
  double Size[2] = {100, 100};
};

#endif
