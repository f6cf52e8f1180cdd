#include "vtkRPLandmarkRegistrationLogic.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>

#include "rpTREMap.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLinearTransformNode.h"

vtkStandardNewMacro(vtkRPLandmarkRegistrationLogic);

namespace {
std::string Number(double value) {
  if (!std::isfinite(value)) return "nan";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

std::string Numbers(const std::vector<double>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) out += (i ? " " : "") + Number(values[i]);
  return out;
}
}  // namespace

vtkRPLandmarkRegistrationLogic::vtkRPLandmarkRegistrationLogic() : Callback(vtkSmartPointer<vtkCallbackCommand>::New()) {
  this->Callback->SetClientData(this);
  this->Callback->SetCallback(&vtkRPLandmarkRegistrationLogic::OnListModified);
  // The same defaults as `roboplan register`: a Polaris's FLE and a 2 mm FRE threshold.
  this->Options.FLE = 0.25;
  this->Options.FREThreshold = 2.0;
}

vtkRPLandmarkRegistrationLogic::~vtkRPLandmarkRegistrationLogic() {
  this->Observe(this->From, this->FromTag, nullptr);
  this->Observe(this->To, this->ToTag, nullptr);
}

void vtkRPLandmarkRegistrationLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << rp::RegistrationModeName(this->GetMode()) << "\n"
     << indent << "FREThreshold: " << this->Options.FREThreshold << "\n"
     << indent << "FLE: " << this->Options.FLE << "\n"
     << indent << "AutoUpdate: " << this->AutoUpdate << "\n"
     << indent << "Last: " << this->Last.Reason << "\n";
}

void vtkRPLandmarkRegistrationLogic::Observe(vtkSmartPointer<vtkRPFiducialListNode>& slot, unsigned long& tag,
                                             vtkRPFiducialListNode* list) {
  if (slot == list) return;
  if (slot) slot->RemoveObserver(tag);
  tag = 0;
  slot = list;
  // ModifiedEvent follows every PointAdded/Removed/ModifiedEvent and is batched by
  // StartModify/EndModify, so a batch of point moves recomputes once.
  if (slot) tag = slot->AddObserver(vtkCommand::ModifiedEvent, this->Callback);
}

void vtkRPLandmarkRegistrationLogic::OnListModified(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<vtkRPLandmarkRegistrationLogic*>(clientData)->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::UpdateIfAutomatic() {
  if (this->AutoUpdate && !this->Updating) this->Update();
}

void vtkRPLandmarkRegistrationLogic::SetFromFiducials(vtkRPFiducialListNode* list) {
  this->Observe(this->From, this->FromTag, list);
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetToFiducials(vtkRPFiducialListNode* list) {
  this->Observe(this->To, this->ToTag, list);
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetOutputTransform(vtkRPLinearTransformNode* transform) {
  this->Output = transform;
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetMode(rp::RegistrationMode mode) {
  this->Options.Registration.Mode = mode;
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetFREThreshold(double mm) {
  this->Options.FREThreshold = mm;
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetFLE(double mm) {
  this->Options.FLE = mm;
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetTarget(const double ras[3]) {
  this->Options.Target = Eigen::Vector3d(ras[0], ras[1], ras[2]);
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::ClearTarget() {
  this->Options.Target.reset();
  this->Modified();
  this->UpdateIfAutomatic();
}

void vtkRPLandmarkRegistrationLogic::SetAutoUpdate(bool on) {
  this->AutoUpdate = on;
  this->Modified();
}

void vtkRPLandmarkRegistrationLogic::CollectPairs(rp::PointList& from, rp::PointList& to,
                                                  std::vector<int>& fromIndex) const {
  const int nFrom = this->From->GetNumberOfControlPoints();
  const int nTo = this->To->GetNumberOfControlPoints();
  if (nFrom != nTo) {
    // Unequal lists: pass every point so the registration refuses with both counts.
    for (int i = 0; i < nFrom; ++i) from.emplace_back(this->From->GetNthControlPoint(i).Position);
    for (int i = 0; i < nTo; ++i) to.emplace_back(this->To->GetNthControlPoint(i).Position);
    return;
  }
  for (int i = 0; i < nFrom; ++i) {
    const auto& p = this->From->GetNthControlPoint(i);
    const auto& q = this->To->GetNthControlPoint(i);
    if (!p.Selected || !q.Selected) continue;
    from.emplace_back(p.Position);
    to.emplace_back(q.Position);
    fromIndex.push_back(i);
  }
}

bool vtkRPLandmarkRegistrationLogic::Update() {
  if (!this->From || !this->To || !this->Output) return false;
  this->Updating = true;
  rp::PointList from, to;
  std::vector<int> fromIndex;
  this->CollectPairs(from, to, fromIndex);
  this->Last = rp::AssessRegistration(from, to, this->Options);
  ++this->NumberOfUpdates;
  this->WriteAttributes(fromIndex);
  this->Updating = false;
  this->InvokeEvent(vtkCommand::ModifiedEvent);
  return this->Last.Accepted;
}

void vtkRPLandmarkRegistrationLogic::WriteAttributes(const std::vector<int>& fromIndex) {
  vtkRPLinearTransformNode* node = this->Output;
  const rp::RegistrationAssessment& a = this->Last;
  const int previous = node->StartModify();
  if (a.Accepted) {
    const Eigen::Matrix4d m = a.Solution.Transform.Matrix();
    double elements[16];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) elements[4 * i + j] = m(i, j);
    node->SetMatrixTransformToParent(elements);
  }
  node->SetAttribute("Registration.Status", a.Accepted ? "accepted" : "rejected");
  node->SetAttribute("Registration.Reason", a.Reason);
  node->SetAttribute("Registration.Mode", rp::RegistrationModeName(this->GetMode()));
  node->SetAttribute("Registration.NumberOfPairs", std::to_string(a.Solution.Residuals.size()));
  node->SetAttribute("Registration.FRE", Number(a.Solution.FRE));
  node->SetAttribute("Registration.FREThreshold", Number(this->Options.FREThreshold));
  node->SetAttribute("Registration.Residuals", Numbers(a.Solution.Residuals));
  node->SetAttribute("Registration.LeaveOneOut", Numbers(a.LeaveOneOut));
  node->SetAttribute("Registration.FLE", Number(this->Options.FLE));
  node->SetAttribute("Registration.ExpectedFRE", Number(a.ExpectedFRE));
  node->SetAttribute("Registration.PredictedTRE",
                     Number(this->Options.Target ? a.PredictedTREAtTarget : a.PredictedTREAtCentroid));
  node->SetAttribute("Registration.PredictedTREMax", Number(a.MaxPredictedTREAtFiducials));
  if (this->Options.Target) {
    const Eigen::Vector3d& t = *this->Options.Target;
    node->SetAttribute("Registration.Target", Numbers({t[0], t[1], t[2]}));
  } else {
    node->RemoveAttribute("Registration.Target");
  }
  std::string suspects;
  for (const auto& s : a.Suspects) {
    const int listIndex = s.Index < static_cast<int>(fromIndex.size()) ? fromIndex[static_cast<size_t>(s.Index)] : s.Index;
    suspects += (suspects.empty() ? "" : " ") + std::to_string(listIndex + 1);
  }
  node->SetAttribute("Registration.Suspects", suspects);
  std::string warnings;
  for (const auto& w : a.Warnings) warnings += (warnings.empty() ? "" : " | ") + w;
  node->SetAttribute("Registration.Warnings", warnings);
  node->SetAttribute("Registration.Method", "landmarks");
  for (const char* key : {"Registration.ICP.InlierRMS", "Registration.ICP.AllRMS", "Registration.ICP.Inliers",
                          "Registration.ICP.Iterations"})
    node->RemoveAttribute(key);
  node->EndModify(previous);
}

bool vtkRPLandmarkRegistrationLogic::RefineWithSurfaceICP(vtkRPFiducialListNode* surfacePoints, vtkPolyData* model,
                                                          const rp::SurfaceICPOptions& options) {
  this->LastICP = rp::SurfaceICPResult();
  if (!this->Output || !surfacePoints || !this->Last.Accepted) {
    this->LastICP.Error = "ICP refines an accepted landmark registration: register the landmarks first";
    return false;
  }
  rp::PointList digitized;
  for (const auto& p : surfacePoints->GetControlPoints())
    if (p.Selected) digitized.emplace_back(p.Position);
  this->LastICP = rp::RefineWithSurfaceICP(digitized, model, this->Last.Solution.Transform, options);
  if (!this->LastICP.Ok) return false;
  vtkRPLinearTransformNode* node = this->Output;
  const int previous = node->StartModify();
  const Eigen::Matrix4d m = this->LastICP.Transform.Matrix();
  double elements[16];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) elements[4 * i + j] = m(i, j);
  node->SetMatrixTransformToParent(elements);
  node->SetAttribute("Registration.Method", "landmarks+ICP");
  node->SetAttribute("Registration.ICP.InlierRMS", Number(this->LastICP.InlierRMS));
  node->SetAttribute("Registration.ICP.AllRMS", Number(this->LastICP.AllRMS));
  node->SetAttribute("Registration.ICP.Inliers", std::to_string(this->LastICP.Inliers));
  node->SetAttribute("Registration.ICP.Iterations", std::to_string(this->LastICP.Iterations));
  node->EndModify(previous);
  return true;
}

double vtkRPLandmarkRegistrationLogic::UpdatePredictedTREMap(vtkPolyData* model) const {
  if (!this->To || !(this->Options.FLE > 0)) return std::nan("");
  rp::PointList to;
  for (const auto& p : this->To->GetControlPoints())
    if (p.Selected) to.emplace_back(p.Position);
  return rp::AddPredictedTREArray(model, rp::TREPredictor(to, this->Options.FLE));
}
