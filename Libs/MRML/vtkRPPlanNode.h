#ifndef vtkRPPlanNode_h
#define vtkRPPlanNode_h
// What a surgeon plans to do, as markups Slicer 5 opens (DESIGN.md, "Plans and guidance"): the
// base of the trajectory (and screw) and the cut plane. A plan remembers the CT it was made on
// (`PlannedOn`, rp::VolumeIdentity text: the DICOM series and frame of reference when known, and
// the voxel grid), so that a plan of another patient is named, not used.
#include <string>

#include "vtkRPMarkupsNode.h"

class vtkRPPlanNode : public vtkRPMarkupsNode {
 public:
  vtkTypeMacro(vtkRPPlanNode, vtkRPMarkupsNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The identity of the CT the plan was made on ("" when not known).
  const std::string& GetPlannedOn() const { return this->PlannedOn; }
  void SetPlannedOn(const std::string& identity);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPPlanNode() = default;
  ~vtkRPPlanNode() override = default;

 private:
  vtkRPPlanNode(const vtkRPPlanNode&) = delete;
  void operator=(const vtkRPPlanNode&) = delete;
  std::string PlannedOn;
};

#endif
