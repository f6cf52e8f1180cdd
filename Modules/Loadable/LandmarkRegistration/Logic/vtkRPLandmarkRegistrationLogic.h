#ifndef vtkRPLandmarkRegistrationLogic_h
#define vtkRPLandmarkRegistrationLogic_h
// Landmark registration in the scene: two fiducial lists in ("from", e.g. landmarks digitized
// in Tracker coordinates, and "to", the same landmarks picked in the image, RAS), one linear
// transform node out (e.g. TrackerToRAS). Pairs are matched by index; a pair is left out when
// either of its points is unselected. Points are taken in each list's own coordinates (before
// any parent transform), so the "from" list may be shown under the output transform without
// feeding back. Recomputes when a point moves (the lists' ModifiedEvent). An accepted result
// sets the node's matrix; a rejected one leaves the matrix as it was (the seed discards a
// registration above the FRE threshold). Either way the node's attributes tell the story:
//   Registration.Status       "accepted" | "rejected"
//   Registration.Reason       why, with the numbers
//   Registration.Mode         "rigid" | "similarity"
//   Registration.NumberOfPairs, Registration.FRE (mm), Registration.FREThreshold (mm)
//   Registration.Residuals    one value per pair, space separated (mm)
//   Registration.LeaveOneOut  one value per pair (mm)
//   Registration.FLE, Registration.ExpectedFRE, Registration.PredictedTRE (at the target, or
//   at the centroid of the "to" points when no target is set), Registration.PredictedTREMax
//   (largest at a "to" fiducial), Registration.Target ("r a s" when set)
//   Registration.Suspects     1-based pair numbers flagged by leave-one-out, space separated
//   Registration.Warnings     warnings joined by " | "
// After RefineWithSurfaceICP (optional), also Registration.Method "landmarks+ICP" and
// Registration.ICP.InlierRMS / AllRMS / Inliers / Iterations: a surface distance, reported apart
// from FRE. A landmark recompute (a point moved) replaces the refined result and drops these.
#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpRegistrationAccuracy.h"
#include "rpSurfaceICP.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"

class vtkCallbackCommand;
class vtkPolyData;

class vtkRPLandmarkRegistrationLogic : public vtkObject {
 public:
  static vtkRPLandmarkRegistrationLogic* New();
  vtkTypeMacro(vtkRPLandmarkRegistrationLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The lists are observed (not owned beyond a reference) while set.
  void SetFromFiducials(vtkRPFiducialListNode* list);
  void SetToFiducials(vtkRPFiducialListNode* list);
  void SetOutputTransform(vtkRPLinearTransformNode* transform);
  vtkRPFiducialListNode* GetFromFiducials() const { return this->From; }
  vtkRPFiducialListNode* GetToFiducials() const { return this->To; }
  vtkRPLinearTransformNode* GetOutputTransform() const { return this->Output; }

  void SetMode(rp::RegistrationMode mode);
  rp::RegistrationMode GetMode() const { return this->Options.Registration.Mode; }
  /// mm; ≤ 0 disables the threshold. Default 2 mm.
  void SetFREThreshold(double mm);
  double GetFREThreshold() const { return this->Options.FREThreshold; }
  /// Prior RMS FLE in mm (device specification plus image picking error); ≤ 0: unknown.
  /// Default 0.25 mm (a Polaris alone: add the image picking error in quadrature).
  void SetFLE(double mm);
  double GetFLE() const { return this->Options.FLE; }
  /// Target in the "to" space (RAS) where TRE is predicted.
  void SetTarget(const double ras[3]);
  void ClearTarget();
  /// Recompute automatically when a list changes (default on).
  void SetAutoUpdate(bool on);
  bool GetAutoUpdate() const { return this->AutoUpdate; }

  /// Registers now. Returns true when accepted (and the output matrix was set).
  bool Update();
  const rp::RegistrationAssessment& GetLastAssessment() const { return this->Last; }
  int GetNumberOfUpdates() const { return this->NumberOfUpdates; }

  /// Refines the current (accepted) registration by trimmed rigid ICP of points digitized on the
  /// patient's surface (in the "from" space, their own coordinates) to `model` (in the "to"
  /// space). Sets the output matrix and the ICP attributes when it succeeds.
  bool RefineWithSurfaceICP(vtkRPFiducialListNode* surfacePoints, vtkPolyData* model,
                            const rp::SurfaceICPOptions& options = {});
  const rp::SurfaceICPResult& GetLastICPResult() const { return this->LastICP; }

  /// Adds the predicted TRE array ("PredictedTRE", mm per point) to a model in the "to" space,
  /// from the current "to" fiducials and FLE. Returns the largest value, NaN if not possible.
  double UpdatePredictedTREMap(vtkPolyData* model) const;

 protected:
  vtkRPLandmarkRegistrationLogic();
  ~vtkRPLandmarkRegistrationLogic() override;

 private:
  vtkRPLandmarkRegistrationLogic(const vtkRPLandmarkRegistrationLogic&) = delete;
  void operator=(const vtkRPLandmarkRegistrationLogic&) = delete;

  static void OnListModified(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  void Observe(vtkSmartPointer<vtkRPFiducialListNode>& slot, unsigned long& tag, vtkRPFiducialListNode* list);
  void CollectPairs(rp::PointList& from, rp::PointList& to, std::vector<int>& fromIndex) const;
  void WriteAttributes(const std::vector<int>& fromIndex);
  void UpdateIfAutomatic();

  vtkSmartPointer<vtkRPFiducialListNode> From, To;
  vtkSmartPointer<vtkRPLinearTransformNode> Output;
  unsigned long FromTag = 0, ToTag = 0;
  vtkSmartPointer<vtkCallbackCommand> Callback;
  rp::AssessmentOptions Options;
  rp::RegistrationAssessment Last;
  rp::SurfaceICPResult LastICP;
  bool AutoUpdate = true;
  bool Updating = false;
  int NumberOfUpdates = 0;
};

#endif
