#pragma once
// Pivot calibration of a stylus tip: from poses of the stylus (StylusToTracker, or
// StylusToReference) while its tip rests in a divot, solve R_i·tip + t_i = pivot in the least
// squares sense. Gives StylusTipToStylus (the tip offset), the pivot point, the RMSE of the
// residuals and whether the result passes the rejection threshold.
#include <array>
#include <string>
#include <vector>

#include "rpToolPose.h"

namespace rp {

struct PivotResult {
  bool Valid = false;          // solved (enough poses, enough rotation)
  bool Accepted = false;       // Valid and RMSE <= threshold
  std::array<double, 3> TipOffset{};   // in the stylus frame (StylusTipToStylus translation)
  std::array<double, 3> PivotPoint{};  // in the tracker/reference frame
  double Rmse = 0;             // mm
  double MaxError = 0;         // mm
  double RotationSpreadDeg = 0;  // largest angle between any used pose and the mean
  size_t PosesUsed = 0;
  std::string Message;         // why it was not valid/accepted
};

/// poses: only OK poses are used. thresholdMm: RMSE above it rejects. minSpreadDeg: the stylus
/// must turn at least this much or the problem is ill-posed.
PivotResult PivotCalibrate(const std::vector<ToolPose>& poses, double thresholdMm = 1.0, double minSpreadDeg = 10.0);

/// ToolToReference = inverse(ReferenceToTracker) · ToolToTracker (state: worst of both).
ToolPose ToolToReference(const ToolPose& toolToTracker, const ToolPose& referenceToTracker);

/// Row-major StylusTipToStylus (identity rotation, the tip offset as translation).
void TipOffsetMatrix(const std::array<double, 3>& tip, double m[16]);

}  // namespace rp
