#pragma once
// A map of predicted TRE over a model's surface: one value per point (mm), stored as a point
// scalar array the viewer colours. The prediction is Fitzpatrick-West-Maurer from a prior FLE
// (see rpRegistrationAccuracy.h); the model must be in the space of the predictor's fiducials.
#include <string>

class vtkPolyData;

namespace rp {

class TREPredictor;

/// Adds (or replaces) the point array `arrayName` and makes it the active scalars. Returns the
/// largest predicted TRE on the surface, or NaN when the model has no points.
double AddPredictedTREArray(vtkPolyData* model, const TREPredictor& predictor,
                            const std::string& arrayName = "PredictedTRE");

}  // namespace rp
