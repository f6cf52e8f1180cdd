#pragma once
// The outline where a plane cuts a triangle mesh, fast for the case a slice view has: the plane
// moves along a fixed normal (a slice following a tool) many times a second. For a normal, each
// triangle's extent along it ([min, max] of its vertices' projections) is sorted once into
// buckets about as wide as a triangle is tall along the normal (a triangle in about two); a cut
// then looks only at the triangles of the bucket the plane falls in — a few thousand of a
// million — instead of evaluating every point and cell as vtkCutter does. The buckets are
// rebuilt when the mesh or the normal changes. The output is line segments (two points each,
// not merged), in the mesh's coordinates.
#include <array>
#include <cstdint>
#include <vector>

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

class vtkPolyData;

namespace rp {

class PlaneCutter {
 public:
  PlaneCutter();
  ~PlaneCutter();
  PlaneCutter(const PlaneCutter&) = delete;
  PlaneCutter& operator=(const PlaneCutter&) = delete;

  void SetInput(vtkPolyData* mesh);
  vtkPolyData* GetInput() const { return this->Input; }
  /// Cuts with the plane n·x = offset (n need not be unit length; it is normalized). Writes the
  /// segments into `output` (replacing its points and lines). Returns the number of segments.
  vtkIdType Cut(const double normal[3], double offset, vtkPolyData* output);
  /// Times the buckets were (re)built (tests).
  int GetNumberOfBuilds() const { return this->Builds; }
  /// Bucket entries per triangle, the index's size (tests).
  double GetEntriesPerTriangle() const;

 private:
  void Build(const double normal[3]);
  vtkMTimeType MeshTime() const;

  vtkSmartPointer<vtkPolyData> Input;
  vtkMTimeType BuiltTime = 0;
  std::array<double, 3> BuiltNormal{{0, 0, 0}};
  std::vector<std::array<vtkIdType, 3>> Triangles;  // polys as triangles (fans for polygons)
  std::vector<double> Projection;                   // n·p for every point
  double Lowest = 0, BucketWidth = 1;
  std::vector<std::uint32_t> BucketStart;      // bucket k's triangles: BucketTriangles[BucketStart[k], BucketStart[k + 1])
  std::vector<std::uint32_t> BucketTriangles;  // triangle indices overlapping each bucket
  int Builds = 0;
};

}  // namespace rp
