#include "rpPlanPictures.h"

#include <algorithm>
#include <cmath>

#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

#include "rpBenchmarkChart.h"
#include "rpSiblingLibrary.h"

namespace rp {

bool WriteProfileChart(const std::string& path, const TrajectoryFigures& figures, const TissueModel& tissue,
                       const std::string& planName, std::string& error) {
  if (figures.Profile.empty()) {
    error = "no HU profile to chart (no CT)";
    return false;
  }
  bench::Series axis{"on the axis", {}, {}}, mean{"cross-section mean", {}, {}}, low{"cross-section min", {}, {}},
      high{"cross-section max", {}, {}};
  for (const ProfileSample& s : figures.Profile) {
    axis.X.push_back(s.DepthMm), axis.Y.push_back(s.HU);
    mean.X.push_back(s.DepthMm), mean.Y.push_back(s.MeanHU);
    low.X.push_back(s.DepthMm), low.Y.push_back(s.MinHU);
    high.X.push_back(s.DepthMm), high.Y.push_back(s.MaxHU);
  }
  std::vector<bench::Series> series = {axis, mean, low, high};
  // The bone ranges of materials.json: a line where each begins (cortical above the first).
  const double x0 = figures.Profile.front().DepthMm, x1 = figures.Profile.back().DepthMm;
  for (const BoneHURange& r : tissue.BoneRanges)
    series.push_back({r.Tissue + " from " + std::to_string(static_cast<int>(r.MinHU)) + " HU", {x0, x1}, {r.MinHU, r.MinHU}});
  bench::ChartOptions options;
  options.Title = "CT numbers along " + planName + " (tool " + std::to_string(figures.ToolDiameterMm).substr(0, 4) + " mm)";
  options.XLabel = "depth from the entry (mm)";
  options.YLabel = "HU";
  return bench::WriteChartPNG(path, series, options, error);
}

vtkSmartPointer<vtkPolyData> SpherePolyData(const double center[3], double radius) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(const_cast<double*>(center));
  sphere->SetRadius(radius);
  const int resolution = std::clamp(static_cast<int>(std::ceil(2 * 3.14159265 * radius)), 16, 720);
  sphere->SetThetaResolution(resolution);
  sphere->SetPhiResolution(resolution / 2);
  sphere->Update();
  return sphere->GetOutput();
}

bool WriteRiskMapPicture(const std::string& path, vtkPolyData* riskMap, const std::vector<StructureAtRiskSnapshot>& structures,
                         const double target[3], const std::vector<Vec3>& candidates, const ProposalResult& result,
                         std::string& error) {
  std::string why;
  const auto draw = SiblingLibraryFunction<RiskMapPictureFunction>(reinterpret_cast<const void*>(&WriteRiskMapPicture),
                                                                   PlanningPicturesLibrary, "roboplan_write_risk_map_picture", why);
  if (!draw) {
    error = "picture '" + path + "' not drawn: " + why;
    return false;
  }
  return draw(path, riskMap, structures, target, candidates, result, error);
}

}  // namespace rp
