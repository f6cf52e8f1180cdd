#include "rpTREMap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include "rpRegistrationAccuracy.h"

namespace rp {

double AddPredictedTREArray(vtkPolyData* model, const TREPredictor& predictor, const std::string& arrayName) {
  if (!model || model->GetNumberOfPoints() == 0) return std::numeric_limits<double>::quiet_NaN();
  vtkNew<vtkDoubleArray> values;
  values->SetName(arrayName.c_str());
  values->SetNumberOfComponents(1);
  values->SetNumberOfTuples(model->GetNumberOfPoints());
  double largest = 0;
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i) {
    double p[3];
    model->GetPoint(i, p);
    const double tre = predictor.PredictRMS(Eigen::Vector3d(p[0], p[1], p[2]));
    values->SetValue(i, tre);
    largest = std::max(largest, tre);
  }
  model->GetPointData()->RemoveArray(arrayName.c_str());
  model->GetPointData()->AddArray(values);
  model->GetPointData()->SetActiveScalars(arrayName.c_str());
  return largest;
}

}  // namespace rp
