#ifndef vtkRPTrackedToolNode_h
#define vtkRPTrackedToolNode_h
// A tracked tool: a linear transform (e.g. StylusToTracker) plus the tracker's status for it
// and the time of the pose. Written only on the main thread (a timer copies what the tracker
// I/O thread published).
#include "vtkRPLinearTransformNode.h"

class vtkRPTrackedToolNode : public vtkRPLinearTransformNode {
 public:
  static vtkRPTrackedToolNode* New();
  vtkTypeMacro(vtkRPTrackedToolNode, vtkRPLinearTransformNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "TrackedTool"; }

  enum Status { StatusUnknown = 0, StatusOK, StatusMissing, StatusOutOfVolume, StatusStale, StatusDisabled };
  static const char* GetStatusAsString(int status);
  static int GetStatusFromString(const std::string& text);  // StatusUnknown when not recognised

  vtkGetMacro(Status, int);
  vtkSetClampMacro(Status, int, StatusUnknown, StatusDisabled);
  /// Time of the pose in seconds (tracker clock or steady clock of the receiving host).
  vtkGetMacro(Timestamp, double);
  vtkSetMacro(Timestamp, double);
  /// Tracker-reported quality (e.g. NDI RMS marker fit error, mm); negative when unknown.
  vtkGetMacro(ErrorRMS, double);
  vtkSetMacro(ErrorRMS, double);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPTrackedToolNode() = default;
  ~vtkRPTrackedToolNode() override = default;

 private:
  vtkRPTrackedToolNode(const vtkRPTrackedToolNode&) = delete;
  void operator=(const vtkRPTrackedToolNode&) = delete;
  int Status = StatusUnknown;
  double Timestamp = 0.0;
  double ErrorRMS = -1.0;
};

#endif
