#ifndef vtkRPTrajectoryNode_h
#define vtkRPTrajectoryNode_h
// A planned trajectory: Slicer's markups line ("MarkupsLine"; control point 0 the entry, 1 the
// target) and what Slicer's line does not know: the diameter of the tool that follows it and the
// tissue it is meant to go through (a tissue class of materials.json, "bone" by default). Name
// and colour are the node's. Points are RAS in the node's frame; the *World getters apply the
// parent transforms.
#include <string>

#include "vtkRPPlanNode.h"

class vtkRPTrajectoryNode : public vtkRPPlanNode {
 public:
  static vtkRPTrajectoryNode* New();
  vtkTypeMacro(vtkRPTrajectoryNode, vtkRPPlanNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Trajectory"; }
  const char* GetMarkupsType() const override { return "Line"; }
  int GetMaximumNumberOfControlPoints() const override { return 2; }

  static constexpr int EntryIndex = 0;
  static constexpr int TargetIndex = 1;

  /// Both points placed.
  bool IsComplete() const { return this->GetNumberOfControlPoints() == 2; }
  /// Places (or moves) the entry and the target in one change (one ModifiedEvent).
  void SetEntryAndTarget(const double entryRAS[3], const double targetRAS[3]);
  /// Moves one end (adds the missing points at the same place first). False when locked.
  bool SetEntry(const double entryRAS[3]);
  bool SetTarget(const double targetRAS[3]);
  /// False when the point is not placed.
  bool GetEntry(double entryRAS[3]) const;
  bool GetTarget(double targetRAS[3]) const;
  bool GetEntryWorld(double entryWorld[3]) const;
  bool GetTargetWorld(double targetWorld[3]) const;
  /// |target - entry| in world mm (0 when incomplete).
  double GetLengthMm() const;

  vtkGetMacro(ToolDiameterMm, double);
  /// Diameter of the tool (drill, burr, pilot hole) that follows the line, mm (> 0).
  void SetToolDiameterMm(double diameter);
  const std::string& GetIntendedTissue() const { return this->IntendedTissue; }
  void SetIntendedTissue(const std::string& tissue);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPTrajectoryNode();
  ~vtkRPTrajectoryNode() override = default;
  bool SetEnd(int index, const double positionRAS[3]);

 private:
  vtkRPTrajectoryNode(const vtkRPTrajectoryNode&) = delete;
  void operator=(const vtkRPTrajectoryNode&) = delete;
  double ToolDiameterMm = 2.0;
  std::string IntendedTissue = "bone";
};

#endif
