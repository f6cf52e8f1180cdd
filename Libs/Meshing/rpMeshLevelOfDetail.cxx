#include "rpMeshLevelOfDetail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include "rpBVH.h"
#include "rpFormat.h"
#include "rpManifoldDecimation.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpTriangleGrid.h"

namespace rp {

double MaxSurfaceDeviation(vtkPolyData* mesh, vtkPolyData* reference) {
  // Each way: the largest distance from a vertex of one surface to the other (exact closest
  // points, queried in parallel). Every vertex of the smaller surface; every k-th vertex of a
  // larger one, at most MaxDeviationSamples (its vertices are spread over the whole surface, about
  // a voxel apart, so the maximum is within a fraction of a voxel of the exact one).
  // `distance2(point, worst2)` is the squared distance from a point to the other surface, or any
  // value no larger than worst2 when it is no larger (such a point cannot raise the maximum).
  auto oneWay = [](const TriangleMesh& from, const auto& distance2) {
    const size_t n = from.Points.size();
    const size_t stride = std::max<size_t>(1, (n + MaxDeviationSamples - 1) / MaxDeviationSamples);
    const vtkIdType samples = static_cast<vtkIdType>((n + stride - 1) / stride);
    vtkSMPThreadLocal<double> worst(0.0);
    vtkSMPTools::For(0, samples, [&](vtkIdType b, vtkIdType e) {
      double& w = worst.Local();
      for (vtkIdType i = b; i < e; ++i) w = std::max(w, distance2(from.Points[static_cast<size_t>(i) * stride], w));
    });
    double result = 0;
    for (double w : worst) result = std::max(result, w);
    return std::sqrt(result);
  };
  TriangleMesh a, b;
  std::string error;
  if (!PolyDataToTriangleMesh(mesh, nullptr, a, error) || !PolyDataToTriangleMesh(reference, nullptr, b, error)) return -1;
  // The larger surface (the full-resolution one, 10^5-10^6 triangles) in a triangle grid, whose
  // linear build costs a fraction of a BVH's (the BVH's build was a third of `roboplan mesh` on a
  // 512x512x300 labelmap), asked first whether a point is within the largest distance so far (it
  // mostly is: the search stops at the first triangle that close). The smaller one, queried as
  // often, in a BVH (few triangles: built on one thread in a few milliseconds).
  const bool aLarger = a.Triangles.size() > b.Triangles.size();
  const TriangleMesh& larger = aLarger ? a : b;
  const TriangleMesh& smaller = aLarger ? b : a;
  TriangleGrid largeGrid;
  largeGrid.Build(larger);
  BVH smallTree;
  smallTree.Build(smaller);
  if (largeGrid.Empty() || smallTree.Empty()) return -1;
  const double toLarger = oneWay(smaller, [&](const Vec3& p, double worst2) {
    if (worst2 > 0 && largeGrid.AnyWithin(p, std::sqrt(worst2))) return 0.0;
    ClosestPointHit hit;
    return largeGrid.ClosestPoint(p, HUGE_VAL, hit) ? hit.Distance2 : 0.0;
  });
  const double toSmaller = oneWay(larger, [&](const Vec3& p, double worst2) {
    ClosestPointHit hit;  // within the largest distance so far: found sooner, and not the maximum
    if (worst2 > 0 && smallTree.ClosestPoint(p, std::sqrt(worst2), hit)) return hit.Distance2;
    return smallTree.ClosestPoint(p, HUGE_VAL, hit) ? hit.Distance2 : 0.0;
  });
  return std::max(toLarger, toSmaller);
}

namespace {

// Keeps the largest components (by enclosed volume) whose triangles fit in `budget`. Returns
// the number left out and their volume.
long KeepComponentsWithin(vtkPolyData* mesh, long budget, double& droppedVolume) {
  droppedVolume = 0;
  const vtkIdType np = mesh->GetNumberOfPoints();
  std::vector<vtkIdType> parent(static_cast<size_t>(np));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](vtkIdType v) {
    while (parent[static_cast<size_t>(v)] != v) v = parent[static_cast<size_t>(v)] = parent[static_cast<size_t>(parent[static_cast<size_t>(v)])];
    return v;
  };
  std::vector<std::array<vtkIdType, 3>> triangles;
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = mesh->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3) continue;
    triangles.push_back({ids[0], ids[1], ids[2]});
    parent[static_cast<size_t>(find(ids[1]))] = find(ids[0]);
    parent[static_cast<size_t>(find(ids[2]))] = find(ids[0]);
  }
  struct Component {
    long Triangles = 0;
    double Volume = 0;
  };
  std::map<vtkIdType, Component> components;
  double a[3], b[3], c[3];
  for (const auto& t : triangles) {
    auto& comp = components[find(t[0])];
    ++comp.Triangles;
    mesh->GetPoint(t[0], a), mesh->GetPoint(t[1], b), mesh->GetPoint(t[2], c);
    comp.Volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
  }
  std::vector<std::pair<double, vtkIdType>> order;
  for (const auto& [root, comp] : components) order.push_back({std::abs(comp.Volume), root});
  std::sort(order.rbegin(), order.rend());
  std::map<vtkIdType, bool> keep;
  long used = 0, dropped = 0;
  for (const auto& [volume, root] : order) {
    const long t = components[root].Triangles;
    const bool fits = used + t <= budget;
    keep[root] = fits;
    if (fits) {
      used += t;
    } else {
      ++dropped;
      droppedVolume += volume;
    }
  }
  if (!dropped) return 0;
  vtkNew<vtkCellArray> kept;
  for (const auto& t : triangles)
    if (keep[find(t[0])]) kept->InsertNextCell(3, t.data());
  mesh->SetPolys(kept);
  mesh->GetPointData()->Initialize();
  return dropped;
}

// 2. Edge collapses from the smallest closed manifold mesh; 3. components left out when even
// that cannot meet the budget. `chosen` is set when the decimation ran.
void ReduceByEdgeCollapse(vtkPolyData* fewest, const MeshStats& fewestStats, long target, const MeshOptions& options,
                          vtkSmartPointer<vtkPolyData>& chosen, MeshStats& chosenStats) {
  DecimationResult decimation;
  vtkSmartPointer<vtkPolyData> mesh = fewest;
  MeshStats s = fewestStats;
  if (DecimateManifold(mesh, target, 0.0, decimation)) {
    s.Method += ", edge collapse";
    if (!decimation.TargetReached) {
      double volume = 0;
      s.DroppedComponents = KeepComponentsWithin(mesh, target, volume);
      s.DroppedVolumeMm3 = volume;
      s.Method += ", " + std::to_string(s.DroppedComponents) + " smallest components left out";
      s.Warnings.push_back(std::to_string(s.DroppedComponents) + " smallest components (" + Format("%.3g", volume) +
                           " mm³) left out: the budget of " + std::to_string(target) +
                           " triangles cannot hold every component");
    }
    ComputeMeshNormals(mesh);
    double volume = 0, area = 0;
    MeshVolumeAndArea(mesh, volume, area);
    if (options.CorrectVolume && !s.DroppedComponents && options.Method != MeshMethod::SlicerDefault &&
        std::abs(volume - s.LabelVolumeMm3) < 0.05 * s.LabelVolumeMm3)
      s.VolumeCorrectionMm = CorrectMeshVolume(mesh, s.LabelVolumeMm3, volume, area);
    const std::string method = s.Method;
    auto warnings = s.Warnings;
    const long droppedComponents = s.DroppedComponents;
    const double droppedVolume = s.DroppedVolumeMm3;
    FillMeshStats(mesh, s, volume, area);
    s.Method = method, s.Warnings = warnings, s.DroppedComponents = droppedComponents, s.DroppedVolumeMm3 = droppedVolume;
    chosen = mesh;
    chosenStats = s;
  }
}

}  // namespace

bool LabelmapToMeshLOD(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, MeshOptions options,
                       const LevelOfDetail& lod, vtkPolyData* output, MeshStats& stats, std::string& error,
                       const ProgressCallback& progress, vtkPolyData* fullResolution,
                       const MeshStats* fullResolutionStats) {
  if (lod.TargetTriangles <= 0 && lod.MaxErrorMm <= 0)
    return LabelmapToMesh(labelmap, ijkToRAS, label, options, output, stats, error, progress);
  auto report = [&](double f, const std::string& m) {
    if (progress) progress(f, m);
  };
  // The full-resolution surface: the reference of every deviation.
  vtkSmartPointer<vtkPolyData> reference = fullResolution;
  MeshStats referenceStats;
  report(0.05, "full-resolution surface");
  if (!reference || reference->GetNumberOfPolys() == 0) {
    reference = vtkSmartPointer<vtkPolyData>::New();
    if (!LabelmapToMesh(labelmap, ijkToRAS, label, options, reference, referenceStats, error)) return false;
  } else if (fullResolutionStats) {
    referenceStats = *fullResolutionStats;
  } else {
    referenceStats.Method = MeshMethodName(options.Method);
    FillMeshStats(reference, referenceStats);
  }
  const long target = lod.TargetTriangles;
  const double base[3] = {options.GridStep[0], options.GridStep[1], options.GridStep[2]};
  auto gridText = [](double step) { return Format("grid %.2g voxels", step); };
  // A trial on a coarser grid: usable when the gaussian surface held (closed, manifold).
  auto trial = [&](double factor, vtkPolyData* mesh, MeshStats& s) {
    MeshOptions o = options;
    for (int a = 0; a < 3; ++a) o.GridStep[a] = base[a] * factor;
    std::string trialError;
    const bool ok = LabelmapToMesh(labelmap, ijkToRAS, label, o, mesh, s, trialError);
    if (ok && s.Method == "gaussian") s.Method = "gaussian, " + gridText(o.GridStep[0]);
    return ok && s.Manifold && s.Method.rfind("gaussian", 0) == 0;
  };

  vtkSmartPointer<vtkPolyData> chosen;  // within the budget
  MeshStats chosenStats;
  vtkSmartPointer<vtkPolyData> fewest;  // the closed manifold mesh with the fewest triangles so far
  MeshStats fewestStats;
  auto consider = [&](vtkPolyData* mesh, const MeshStats& s) {
    if (!s.Manifold) return;
    if (!fewest || s.Triangles < fewestStats.Triangles) {
      fewest = vtkSmartPointer<vtkPolyData>::New();
      fewest->DeepCopy(mesh);
      fewestStats = s;
    }
  };
  consider(reference, referenceStats);
  if (target > 0 && referenceStats.Triangles <= target) {
    chosen = reference;
    chosenStats = referenceStats;
  }
  // 1. Coarser contour grids (gaussian only): the finest grid within the budget.
  if (target > 0 && !chosen && options.Method == MeshMethod::Gaussian) {
    double lo = 1.0, hi = 0.0;  // lo: too many triangles; hi: within budget, or broken
    double factor = 1.03 * std::sqrt(static_cast<double>(referenceStats.Triangles) / static_cast<double>(target));
    for (int iteration = 0; iteration < 8; ++iteration) {
      factor = std::min(std::max(factor, lo * 1.02), 64.0);
      if (hi > 0 && factor >= hi) factor = 0.5 * (lo + hi);
      report(0.1 + 0.08 * iteration, gridText(base[0] * factor));
      vtkNew<vtkPolyData> mesh;
      MeshStats s;
      const bool usable = trial(factor, mesh, s);
      if (usable) consider(mesh, s);
      if (usable && s.Triangles <= target) {
        if (!chosen || s.Triangles > chosenStats.Triangles) {
          chosen = vtkSmartPointer<vtkPolyData>::New();
          chosen->ShallowCopy(mesh);
          chosenStats = s;
        }
        hi = factor;
        if (s.Triangles >= 0.8 * static_cast<double>(target)) break;  // close enough to the budget
        factor = factor * std::sqrt(static_cast<double>(s.Triangles) / static_cast<double>(target));
      } else if (usable) {
        lo = factor;
        factor = factor * 1.03 * std::sqrt(static_cast<double>(s.Triangles) / static_cast<double>(target));
      } else {
        hi = factor;  // broken at this scale: coarser cannot help
        factor = 0.5 * (lo + hi);
      }
      if (hi > 0 && hi / lo < 1.03) break;
    }
  }
  // 2. Edge collapses from the smallest closed manifold mesh; 3. components left out.
  if (target > 0 && !chosen && fewest) {
    report(0.8, "edge collapse");
    ReduceByEdgeCollapse(fewest, fewestStats, target, options, chosen, chosenStats);
  }
  // A deviation bound without a triangle budget: the coarsest grid within it.
  if (target <= 0 && lod.MaxErrorMm > 0) {
    chosen = reference;
    chosenStats = referenceStats;
    if (options.Method == MeshMethod::Gaussian) {
      for (double factor = 1.3; factor < 64; factor *= 1.3) {
        report(std::min(0.9, 0.1 * factor), gridText(base[0] * factor));
        vtkNew<vtkPolyData> mesh;
        MeshStats s;
        if (!trial(factor, mesh, s) || MaxSurfaceDeviation(mesh, reference) > lod.MaxErrorMm) break;
        chosen = vtkSmartPointer<vtkPolyData>::New();
        chosen->ShallowCopy(mesh);
        chosenStats = s;
      }
    }
  }
  if (!chosen) {
    // Nothing closed and manifold to reduce (a method that gave neither): say so, keep the surface.
    chosen = reference;
    chosenStats = referenceStats;
    chosenStats.Warnings.push_back("no closed manifold surface to reduce: the budget of " + std::to_string(target) +
                                   " triangles is not met");
  }
  output->ShallowCopy(chosen);
  stats = chosenStats;
  stats.BudgetTriangles = target;
  stats.WithinBudget = target <= 0 || stats.Triangles <= target;
  report(0.95, "deviation from the full-resolution surface");
  stats.MaxDeviationMm = chosen == reference ? 0.0 : MaxSurfaceDeviation(output, reference);
  if (lod.MaxErrorMm > 0 && stats.MaxDeviationMm > lod.MaxErrorMm)
    stats.Warnings.push_back("level of detail deviates " + Format("%.2f", stats.MaxDeviationMm) +
                             " mm from the full-resolution surface (bound " + Format("%.2f", lod.MaxErrorMm) + " mm)");
  report(1.0, "done");
  return true;
}

}  // namespace rp
