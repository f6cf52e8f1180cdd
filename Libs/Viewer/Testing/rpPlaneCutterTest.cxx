// The fast plane cut against the known answer (a sphere's circle) and against vtkCutter on the
// same mesh (same total outline length), the buckets built once per normal, and an index of a
// few entries a triangle.
#include <gtest/gtest.h>

#include <cmath>

#include <vtkCellArray.h>
#include <vtkCutter.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

#include "rpPlaneCutter.h"

namespace {
double OutlineLength(vtkPolyData* lines) {
  double length = 0;
  vtkCellArray* cells = lines->GetLines();
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  for (cells->InitTraversal(); cells->GetNextCell(n, ids);) {
    for (vtkIdType k = 0; k + 1 < n; ++k) {
      double a[3], b[3];
      lines->GetPoint(ids[k], a);
      lines->GetPoint(ids[k + 1], b);
      length += std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    }
  }
  return length;
}
}  // namespace

TEST(PlaneCutter, SphereCutIsACircleAndMatchesVtkCutter) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(3, -2, 5);
  sphere->SetRadius(20);
  sphere->SetThetaResolution(128);
  sphere->SetPhiResolution(128);
  sphere->Update();
  rp::PlaneCutter cutter;
  cutter.SetInput(sphere->GetOutput());
  vtkNew<vtkPolyData> outline;
  const double normal[3] = {0, 0, 2};  // not unit: normalized inside (plane z = offset / 2 · 2)
  for (double z : {5.0, 17.0, -11.0}) {
    ASSERT_GT(cutter.Cut(normal, 2 * z, outline), 100) << z;
    const double radius = std::sqrt(400 - (z - 5) * (z - 5));
    for (vtkIdType i = 0; i < outline->GetNumberOfPoints(); ++i) {
      double p[3];
      outline->GetPoint(i, p);
      EXPECT_NEAR(p[2], z, 1e-9);
      EXPECT_NEAR(std::hypot(p[0] - 3, p[1] + 2), radius, 0.05);
    }
  }
  EXPECT_EQ(cutter.GetNumberOfBuilds(), 1);  // moving along one normal needs no rebuild
  // The index holds each triangle in a few buckets, not in dozens (its memory).
  EXPECT_GT(cutter.GetEntriesPerTriangle(), 1.0);
  EXPECT_LE(cutter.GetEntriesPerTriangle(), 4.0);

  // An oblique plane: the same outline as VTK's cutter (length to a part in a million).
  const double oblique[3] = {0.3, -0.5, 0.8};
  const double origin[3] = {4, -1, 7};
  const double offset = vtkMath::Dot(oblique, origin);
  cutter.Cut(oblique, offset, outline);
  EXPECT_EQ(cutter.GetNumberOfBuilds(), 2);
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(origin[0], origin[1], origin[2]);
  plane->SetNormal(oblique[0], oblique[1], oblique[2]);
  vtkNew<vtkCutter> reference;
  reference->SetInputConnection(sphere->GetOutputPort());
  reference->SetCutFunction(plane);
  reference->Update();
  const double expected = OutlineLength(reference->GetOutput());
  ASSERT_GT(expected, 100);
  EXPECT_NEAR(OutlineLength(outline), expected, 1e-6 * expected);

  // Outside the mesh: nothing; a changed mesh: rebuilt.
  EXPECT_EQ(cutter.Cut(normal, 2 * 40.0, outline), 0);
  sphere->SetRadius(10);
  sphere->Update();
  cutter.SetInput(sphere->GetOutput());
  EXPECT_GT(cutter.Cut(normal, 2 * 5.0, outline), 0);
  double p[3];
  outline->GetPoint(0, p);
  EXPECT_NEAR(std::hypot(p[0] - 3, p[1] + 2), 10, 0.05);
  // A degenerate normal or no mesh: nothing, no crash.
  const double zero[3] = {0, 0, 0};
  EXPECT_EQ(cutter.Cut(zero, 0, outline), 0);
  rp::PlaneCutter empty;
  EXPECT_EQ(empty.Cut(normal, 0, outline), 0);
}
