#ifndef vtkRPScrewNode_h
#define vtkRPScrewNode_h
// A planned screw: a trajectory (entry, target, the pilot drill's diameter) plus the screw's
// diameter, length and head. The screw lies on the line with its tip at the target and its shaft
// running `ScrewLengthMm` back towards the entry; the head (a cylinder of HeadDiameterMm x
// HeadLengthMm) sits beyond the shaft's end. Slicer sees the line (a MarkupsLine with our fields
// as attributes) and the screw's closed surface as a model (the "screwModel" reference; the
// Planning module builds and updates it, rp::MakeScrewMesh).
#include "vtkRPTrajectoryNode.h"

class vtkRPScrewNode : public vtkRPTrajectoryNode {
 public:
  static vtkRPScrewNode* New();
  vtkTypeMacro(vtkRPScrewNode, vtkRPTrajectoryNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Screw"; }

  static const char* ScrewModelRole() { return "screwModel"; }

  vtkGetMacro(ScrewDiameterMm, double);
  vtkGetMacro(ScrewLengthMm, double);
  vtkGetMacro(HeadDiameterMm, double);
  vtkGetMacro(HeadLengthMm, double);
  /// Each > 0 (others are ignored); the head may be 0 long (a headless screw).
  void SetScrewDiameterMm(double mm);
  void SetScrewLengthMm(double mm);
  void SetHeadDiameterMm(double mm);
  void SetHeadLengthMm(double mm);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPScrewNode();
  ~vtkRPScrewNode() override = default;

 private:
  vtkRPScrewNode(const vtkRPScrewNode&) = delete;
  void operator=(const vtkRPScrewNode&) = delete;
  void SetSize(double& field, double mm, bool mayBeZero);
  double ScrewDiameterMm = 6.5;
  double ScrewLengthMm = 40.0;
  double HeadDiameterMm = 10.0;
  double HeadLengthMm = 5.0;
};

#endif
