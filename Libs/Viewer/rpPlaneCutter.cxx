#include "rpPlaneCutter.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIdList.h>
#include <vtkMath.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace rp {

PlaneCutter::PlaneCutter() = default;
PlaneCutter::~PlaneCutter() = default;

void PlaneCutter::SetInput(vtkPolyData* mesh) {
  if (mesh == this->Input) return;
  this->Input = mesh;
  this->BuiltTime = 0;
}

// The geometry's own modification time (points and polygons): the polydata's MTime also moves
// when only caches change (cell links, locators built by other users of the mesh).
vtkMTimeType PlaneCutter::MeshTime() const {
  vtkMTimeType time = 0;
  if (vtkPoints* points = this->Input->GetPoints()) time = std::max(time, points->GetMTime());
  if (vtkCellArray* polys = this->Input->GetPolys()) time = std::max(time, polys->GetMTime());
  return time;
}

void PlaneCutter::Build(const double normal[3]) {
  ++this->Builds;
  this->BuiltTime = this->MeshTime();
  this->BuiltNormal = {normal[0], normal[1], normal[2]};
  this->Triangles.clear();
  this->BucketStart.clear();
  this->BucketTriangles.clear();
  vtkPoints* points = this->Input->GetPoints();
  vtkCellArray* polys = this->Input->GetPolys();
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  this->Projection.resize(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    points->GetPoint(i, p);
    this->Projection[static_cast<size_t>(i)] = vtkMath::Dot(p, normal);
  }
  if (n == 0 || !polys) return;
  auto iter = vtk::TakeSmartPointer(polys->NewIterator());
  vtkIdType size = 0;
  const vtkIdType* ids = nullptr;
  for (iter->GoToFirstCell(); !iter->IsDoneWithTraversal(); iter->GoToNextCell()) {
    iter->GetCurrentCell(size, ids);
    for (vtkIdType k = 1; k + 1 < size; ++k) this->Triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  if (this->Triangles.empty()) return;
  // Each triangle's extent along the normal.
  std::vector<std::pair<double, double>> extents(this->Triangles.size());
  double lowest = VTK_DOUBLE_MAX, highest = -VTK_DOUBLE_MAX, sum = 0;
  for (size_t t = 0; t < this->Triangles.size(); ++t) {
    const auto& tri = this->Triangles[t];
    double a = this->Projection[static_cast<size_t>(tri[0])], b = a;
    for (int v = 1; v < 3; ++v) {
      a = std::min(a, this->Projection[static_cast<size_t>(tri[v])]);
      b = std::max(b, this->Projection[static_cast<size_t>(tri[v])]);
    }
    extents[t] = {a, b};
    lowest = std::min(lowest, a);
    highest = std::max(highest, b);
    sum += b - a;
  }
  this->Lowest = lowest;
  // Buckets about as wide as a triangle is tall along the normal, so a triangle falls in about
  // two of them: a cut reads the triangles near the plane, and the index stays a few entries a
  // triangle (buckets of a fixed count were a hundredth of a millimetre on a fine mesh, and a
  // triangle sat in fifty of them: hundreds of MB per model and normal).
  const double range = highest - lowest;
  this->BucketWidth = std::max({sum / double(this->Triangles.size()), range / 65536.0, 1e-9});
  const size_t buckets = std::max<size_t>(1, static_cast<size_t>(range / this->BucketWidth) + 1);
  auto bucketOf = [&](double x) { return std::min(buckets - 1, static_cast<size_t>((x - lowest) / this->BucketWidth)); };
  // Compressed rows: count, prefix sums, fill.
  this->BucketStart.assign(buckets + 1, 0);
  for (const auto& [a, b] : extents) {
    for (size_t k = bucketOf(a); k <= bucketOf(b); ++k) ++this->BucketStart[k + 1];
  }
  for (size_t k = 0; k < buckets; ++k) this->BucketStart[k + 1] += this->BucketStart[k];
  this->BucketTriangles.resize(this->BucketStart[buckets]);
  std::vector<std::uint32_t> fill(this->BucketStart.begin(), this->BucketStart.end() - 1);
  for (size_t t = 0; t < extents.size(); ++t) {
    for (size_t k = bucketOf(extents[t].first); k <= bucketOf(extents[t].second); ++k) {
      this->BucketTriangles[fill[k]++] = static_cast<std::uint32_t>(t);
    }
  }
}

double PlaneCutter::GetEntriesPerTriangle() const {
  return this->Triangles.empty() ? 0.0 : double(this->BucketTriangles.size()) / double(this->Triangles.size());
}

vtkIdType PlaneCutter::Cut(const double normalIn[3], double offset, vtkPolyData* output) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  double normal[3] = {normalIn[0], normalIn[1], normalIn[2]};
  const double length = vtkMath::Normalize(normal);
  vtkPoints* meshPoints = this->Input ? this->Input->GetPoints() : nullptr;
  if (!meshPoints || length <= 0 || !std::isfinite(offset)) {
    output->SetPoints(points);
    output->SetLines(lines);
    return 0;
  }
  offset /= length;
  const bool sameNormal = std::fabs(normal[0] - this->BuiltNormal[0]) < 1e-12 &&
                          std::fabs(normal[1] - this->BuiltNormal[1]) < 1e-12 &&
                          std::fabs(normal[2] - this->BuiltNormal[2]) < 1e-12;
  if (!sameNormal || this->BuiltTime != this->MeshTime()) {
    this->Build(normal);
  }
  // The triangles of the bucket the plane falls in: [first, last).
  const std::uint32_t* first = nullptr;
  const std::uint32_t* last = nullptr;
  const size_t buckets = this->BucketStart.empty() ? 0 : this->BucketStart.size() - 1;
  const double position = buckets ? (offset - this->Lowest) / this->BucketWidth : -1;
  if (position >= 0 && position <= double(buckets)) {
    const size_t bucket = std::min(buckets - 1, static_cast<size_t>(position));
    first = this->BucketTriangles.data() + this->BucketStart[bucket];
    last = this->BucketTriangles.data() + this->BucketStart[bucket + 1];
  }
  // At most one segment a triangle of the bucket: the output is sized once and written in place
  // (a slice view re-cuts every frame while a tool moves; inserting point by point cost more
  // than the geometry). Float points are read directly, others through vtkPoints.
  vtkNew<vtkFloatArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(2 * static_cast<vtkIdType>(last - first));
  float* out = coordinates->GetPointer(0);
  auto* floats = vtkFloatArray::FastDownCast(meshPoints->GetData());
  const float* in = floats ? floats->GetPointer(0) : nullptr;
  auto point = [&](vtkIdType id, double p[3]) {
    if (in) {
      for (int c = 0; c < 3; ++c) p[c] = in[3 * id + c];
    } else {
      meshPoints->GetPoint(id, p);
    }
  };
  vtkIdType segments = 0;
  for (const std::uint32_t* t = first; t != last; ++t) {
    const auto& tri = this->Triangles[*t];
    double d[3];
    for (int v = 0; v < 3; ++v) d[v] = this->Projection[static_cast<size_t>(tri[v])] - offset;
    // The segment joins the crossings of the edges whose ends lie on opposite sides.
    int found = 0;
    for (int e = 0; e < 3 && found < 2; ++e) {
      const int i = e, j = (e + 1) % 3;
      if ((d[i] < 0) == (d[j] < 0)) continue;
      double p[3], q[3];
      point(tri[i], p);
      point(tri[j], q);
      const double s = d[i] / (d[i] - d[j]);
      float* end = out + 3 * (2 * segments + found);
      for (int c = 0; c < 3; ++c) end[c] = static_cast<float>(p[c] + s * (q[c] - p[c]));
      ++found;
    }
    if (found == 2) ++segments;
  }
  coordinates->SetNumberOfTuples(2 * segments);
  points->SetData(coordinates);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(segments + 1);
  connectivity->SetNumberOfTuples(2 * segments);
  vtkIdType* o = offsets->GetPointer(0);
  vtkIdType* c = connectivity->GetPointer(0);
  for (vtkIdType k = 0; k <= segments; ++k) o[k] = 2 * k;
  for (vtkIdType k = 0; k < 2 * segments; ++k) c[k] = k;
  lines->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetLines(lines);
  output->Modified();
  return segments;
}

}  // namespace rp
