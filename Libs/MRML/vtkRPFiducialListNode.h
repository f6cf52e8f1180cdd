#ifndef vtkRPFiducialListNode_h
#define vtkRPFiducialListNode_h
// A list of control points (Slicer's markups fiducial list): label, RAS position, selected,
// locked, visible. Moving a point fires PointModifiedEvent (callData = int* index) and one
// ModifiedEvent, so a registration can recompute when a point moves.
#include <string>
#include <vector>

#include "rpControlPoint.h"
#include "vtkRPTransformableNode.h"

class vtkRPFiducialListNode : public vtkRPTransformableNode {
 public:
  static vtkRPFiducialListNode* New();
  vtkTypeMacro(vtkRPFiducialListNode, vtkRPTransformableNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "FiducialList"; }

  enum { PointAddedEvent = 32000, PointRemovedEvent, PointModifiedEvent };

  using ControlPoint = rp::ControlPoint;

  int GetNumberOfControlPoints() const { return static_cast<int>(this->Points.size()); }
  const ControlPoint& GetNthControlPoint(int n) const { return this->Points.at(static_cast<size_t>(n)); }
  const std::vector<ControlPoint>& GetControlPoints() const { return this->Points; }
  /// Adds a point; a label is generated ("<list name>-<n>") when empty. Returns its index.
  int AddControlPoint(const double positionRAS[3], const std::string& label = "");
  int AddControlPoint(const ControlPoint& point);
  bool SetNthControlPointPosition(int n, const double positionRAS[3]);  // refused if locked
  void GetNthControlPointPosition(int n, double positionRAS[3]) const;
  /// Position with the parent transforms applied (world RAS).
  void GetNthControlPointPositionWorld(int n, double positionWorld[3]) const;
  void SetNthControlPointLabel(int n, const std::string& label);
  void SetNthControlPointSelected(int n, bool selected);
  void SetNthControlPointLocked(int n, bool locked);
  void RemoveNthControlPoint(int n);
  void RemoveAllControlPoints();
  /// Index of the point with this label, -1 when absent.
  int GetControlPointIndexByLabel(const std::string& label) const;
  /// Whether a label is of the generated form "<list name>-<number>" (not one a user chose).
  bool IsGeneratedLabel(const std::string& label) const;

  /// Display (used by the viewer).
  vtkGetVector3Macro(Color, double);
  vtkSetVector3Macro(Color, double);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPFiducialListNode() = default;
  ~vtkRPFiducialListNode() override = default;

 private:
  vtkRPFiducialListNode(const vtkRPFiducialListNode&) = delete;
  void operator=(const vtkRPFiducialListNode&) = delete;
  std::string NextPointID();
  std::string LabelPrefix() const;  // "<list name>-" ("F-" for an unnamed list)
  std::vector<ControlPoint> Points;
  int LastPointNumber = 0;
  double Color[3] = {1.0, 0.5, 0.5};
};

#endif
