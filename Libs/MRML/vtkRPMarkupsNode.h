#ifndef vtkRPMarkupsNode_h
#define vtkRPMarkupsNode_h
// Control points in RAS (Slicer's vtkMRMLMarkupsNode): label, position, selected, locked,
// visible, and the display colour. The base of the fiducial list (any number of points), the
// trajectory (a line: entry and target) and the cut plane (its origin). Moving a point fires
// PointModifiedEvent (callData = int* index) and one ModifiedEvent, so whatever measures the
// points (a registration, a plan's figures) can recompute when one moves.
#include <string>
#include <vector>

#include "rpControlPoint.h"
#include "vtkRPTransformableNode.h"

class vtkRPMarkupsNode : public vtkRPTransformableNode {
 public:
  vtkTypeMacro(vtkRPMarkupsNode, vtkRPTransformableNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum { PointAddedEvent = 32000, PointRemovedEvent, PointModifiedEvent };

  using ControlPoint = rp::ControlPoint;

  /// Slicer's markups type, the "type" of a .mrk.json and the MRML tag without "Markups":
  /// "Fiducial", "Line", "Plane".
  virtual const char* GetMarkupsType() const = 0;
  /// Most points this kind holds (-1: any number); AddControlPoint refuses more.
  virtual int GetMaximumNumberOfControlPoints() const { return -1; }

  int GetNumberOfControlPoints() const { return static_cast<int>(this->Points.size()); }
  const ControlPoint& GetNthControlPoint(int n) const { return this->Points.at(static_cast<size_t>(n)); }
  const std::vector<ControlPoint>& GetControlPoints() const { return this->Points; }
  /// Adds a point; a label is generated ("<list name>-<n>") when empty. Returns its index, or -1
  /// when the node holds its maximum number of points already.
  int AddControlPoint(const double positionRAS[3], const std::string& label = "");
  int AddControlPoint(const ControlPoint& point);
  bool SetNthControlPointPosition(int n, const double positionRAS[3]);  // refused if locked
  void GetNthControlPointPosition(int n, double positionRAS[3]) const;
  /// Position with the parent transforms applied (world RAS).
  void GetNthControlPointPositionWorld(int n, double positionWorld[3]) const;
  /// Sets the position from world RAS (the parent transforms undone). Refused if locked.
  bool SetNthControlPointPositionWorld(int n, const double positionWorld[3]);
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
  vtkRPMarkupsNode() = default;
  ~vtkRPMarkupsNode() override = default;
  /// Writes point n's position without events (subclasses batch several changes).
  bool MovePoint(int n, const double positionRAS[3]);

 private:
  vtkRPMarkupsNode(const vtkRPMarkupsNode&) = delete;
  void operator=(const vtkRPMarkupsNode&) = delete;
  std::string NextPointID();
  std::string LabelPrefix() const;  // "<list name>-" ("F-" for an unnamed list)
  std::vector<ControlPoint> Points;
  int LastPointNumber = 0;
  double Color[3] = {1.0, 0.5, 0.5};
};

#endif
