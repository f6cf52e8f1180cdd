// Levels of detail on adversarial labelmaps: one-voxel plates and thin rods, 200 specks, a
// segment filling the volume's border, hundreds of components with a budget too small for all
// of them. Every haptic mesh must meet its triangle budget and be closed and manifold (checked
// here independently of the mesher's own stats), and say what it is (method, deviation).
// Also the edge-collapse decimation alone: closed manifold in, closed manifold out, at any target.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkTriangleFilter.h>

#include "rpLabelmapToMesh.h"
#include "rpBVH.h"
#include "rpManifoldDecimation.h"
#include "rpMeshLevelOfDetail.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSegmentationToModels.h"
#include "vtkRPModelNode.h"
#include "vtkRPSegmentationNode.h"

using namespace rp;

namespace {

struct Labelmap {
  vtkSmartPointer<vtkImageData> Image = vtkSmartPointer<vtkImageData>::New();
  vtkSmartPointer<vtkMatrix4x4> IJKToRAS = vtkSmartPointer<vtkMatrix4x4>::New();
  int Dims[3];
  Labelmap(int nx, int ny, int nz, double sx = 1, double sy = 1, double sz = 1) {
    Dims[0] = nx, Dims[1] = ny, Dims[2] = nz;
    this->Image->SetDimensions(nx, ny, nz);
    this->Image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    this->Image->GetPointData()->GetScalars()->Fill(0);
    this->IJKToRAS->SetElement(0, 0, sx), this->IJKToRAS->SetElement(1, 1, sy), this->IJKToRAS->SetElement(2, 2, sz);
  }
  unsigned char& At(int i, int j, int k) {
    return static_cast<unsigned char*>(this->Image->GetScalarPointer())[(static_cast<size_t>(k) * Dims[1] + j) * Dims[0] + i];
  }
};

// The checks every haptic mesh must pass, computed here from the mesh itself.
void ExpectWithinBudgetClosedManifold(vtkPolyData* mesh, const MeshStats& stats, long budget, const char* what) {
  long boundary = -1, nonManifold = -1;
  CountBadEdges(mesh, boundary, nonManifold);
  EXPECT_GT(mesh->GetNumberOfPolys(), 0) << what;
  EXPECT_LE(mesh->GetNumberOfPolys(), budget) << what;
  EXPECT_EQ(boundary, 0) << what;
  EXPECT_EQ(nonManifold, 0) << what;
  EXPECT_EQ(CountNonManifoldVertices(mesh), 0) << what;
  EXPECT_TRUE(stats.WithinBudget) << what;
  EXPECT_EQ(stats.BudgetTriangles, budget) << what;
  EXPECT_FALSE(stats.Method.empty()) << what;
  EXPECT_GE(stats.MaxDeviationMm, 0.0) << what;
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  EXPECT_GT(volume, 0) << what << ": outward and enclosing something";
  std::printf("%-28s %6ld triangles (budget %ld)  %-60s max deviation %.2f mm  dropped %ld\n", what,
              stats.Triangles, budget, stats.Method.c_str(), stats.MaxDeviationMm, stats.DroppedComponents);
}

MeshStats Haptic(Labelmap& l, long budget, vtkPolyData* mesh, const char* what) {
  MeshStats stats;
  std::string error;
  LevelOfDetail lod;
  lod.TargetTriangles = budget;
  EXPECT_TRUE(LabelmapToMeshLOD(l.Image, l.IJKToRAS, 1, MeshOptions(), lod, mesh, stats, error)) << what << ": " << error;
  ExpectWithinBudgetClosedManifold(mesh, stats, budget, what);
  return stats;
}

}  // namespace

TEST(LevelOfDetail, OneVoxelPlatesAndThinRods) {
  // A 60 x 60 plate one voxel thick, a plate one voxel thick on 0.5 x 0.5 x 2 mm voxels, and
  // eight one-voxel rods (ribs) 50 voxels long.
  Labelmap l(80, 80, 40);
  for (int j = 10; j < 70; ++j)
    for (int i = 10; i < 70; ++i) l.At(i, j, 20) = 1;
  for (int r = 0; r < 8; ++r)
    for (int k = 0; k < 36; ++k) l.At(5 + 9 * r, 75, 2 + k) = 1;
  vtkNew<vtkPolyData> mesh;
  const MeshStats s = Haptic(l, 3000, mesh, "plate + ribs");
  EXPECT_LT(s.MaxDeviationMm, 3.0);

  Labelmap thin(60, 60, 12, 0.5, 0.5, 2.0);
  for (int j = 5; j < 55; ++j)
    for (int i = 5; i < 55; ++i) thin.At(i, j, 6) = 1;
  vtkNew<vtkPolyData> thinMesh;
  Haptic(thin, 1000, thinMesh, "anisotropic plate");
}

TEST(LevelOfDetail, TwoHundredSpecksAndABudgetTooSmallForThem) {
  Labelmap l(64, 64, 64);
  std::mt19937 random(7);
  std::uniform_int_distribution<int> at(2, 58);
  int placed = 0;
  while (placed < 200) {  // single voxels and 2x2x2 cubes, none touching another
    const int i = at(random), j = at(random), k = at(random), size = placed % 2 ? 2 : 1;
    bool free = true;
    for (int dk = -1; dk <= size && free; ++dk)
      for (int dj = -1; dj <= size && free; ++dj)
        for (int di = -1; di <= size && free; ++di) free = l.At(i + di, j + dj, k + dk) == 0;
    if (!free) continue;
    for (int dk = 0; dk < size; ++dk)
      for (int dj = 0; dj < size; ++dj)
        for (int di = 0; di < size; ++di) l.At(i + di, j + dj, k + dk) = 1;
    ++placed;
  }
  vtkNew<vtkPolyData> mesh;
  const MeshStats roomy = Haptic(l, 2000, mesh, "200 specks, 2000 triangles");
  EXPECT_EQ(roomy.DroppedComponents, 0);
  // 500 triangles cannot hold 200 closed components (4 triangles each at least): the smallest
  // are left out and the stats say so.
  vtkNew<vtkPolyData> tight;
  const MeshStats s = Haptic(l, 500, tight, "200 specks, 500 triangles");
  EXPECT_GT(s.DroppedComponents, 0);
  EXPECT_GT(s.DroppedVolumeMm3, 0);
  EXPECT_FALSE(s.Warnings.empty());
}

TEST(LevelOfDetail, SegmentFillingTheVolumeBorder) {
  // Everything labelled but a ball in the middle: the segment touches all six faces.
  Labelmap l(50, 40, 30);
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 50; ++i)
        l.At(i, j, k) = (i - 25) * (i - 25) + (j - 20) * (j - 20) + (k - 15) * (k - 15) > 100 ? 1 : 0;
  vtkNew<vtkPolyData> mesh;
  const MeshStats s = Haptic(l, 2000, mesh, "filling the border");
  EXPECT_TRUE(s.TouchesBorder);
}

TEST(LevelOfDetail, SegmentModelsMeetTheHapticBudgetOnEverySegment) {
  // Through BuildSegmentModels (the path of `roboplan mesh` and the panel): three segments, the
  // haptic budget on each, the display mesh as the full-resolution reference.
  vtkNew<vtkRPSegmentationNode> segmentation;
  Labelmap l(70, 70, 50);
  for (int k = 5; k < 45; ++k)
    for (int j = 5; j < 65; ++j)
      for (int i = 5; i < 65; ++i) {
        const double r2 = (i - 35.0) * (i - 35.0) + (j - 35.0) * (j - 35.0) + (k - 25.0) * (k - 25.0);
        if (r2 < 18 * 18) l.At(i, j, k) = 1;
        else if (k == 44 || j == 64) l.At(i, j, k) = 2;  // one-voxel walls
        else if ((i * 7 + j * 3 + k * 5) % 97 == 0) l.At(i, j, k) = 3;  // scattered specks
      }
  segmentation->SetImageData(l.Image);
  segmentation->SetIJKToRASMatrix(l.IJKToRAS);
  for (int label = 1; label <= 3; ++label) {
    vtkRPSegmentationNode::Segment s;
    s.ID = "segment" + std::to_string(label);
    s.LabelValue = label;
    segmentation->SetSegment(s);
  }
  ModelBuildOptions options;
  options.HapticLOD.TargetTriangles = 1500;
  const auto models = BuildSegmentModels(segmentation, options);
  ASSERT_EQ(models.size(), 3u);
  for (const auto& m : models) {
    ASSERT_TRUE(m.Ok) << m.Error;
    ExpectWithinBudgetClosedManifold(m.HapticModel->GetPolyData(), m.Haptic, 1500, m.SegmentID.c_str());
    EXPECT_TRUE(m.Display.Manifold) << m.SegmentID;
  }
}

TEST(LevelOfDetail, EdgeCollapseKeepsAClosedManifoldAtAnyTarget) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(80);
  sphere->SetPhiResolution(80);
  sphere->SetRadius(10);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(sphere->GetOutputPort());
  triangles->Update();
  // vtkSphereSource has no duplicate points at the poles: a closed manifold.
  for (long target : {5000L, 500L, 50L, 4L}) {
    vtkNew<vtkPolyData> mesh;
    mesh->DeepCopy(triangles->GetOutput());
    DecimationResult r;
    ASSERT_TRUE(DecimateManifold(mesh, target, 0, r));
    long boundary = -1, nonManifold = -1;
    CountBadEdges(mesh, boundary, nonManifold);
    EXPECT_EQ(boundary, 0) << target;
    EXPECT_EQ(nonManifold, 0) << target;
    EXPECT_EQ(CountNonManifoldVertices(mesh), 0) << target;
    EXPECT_LE(mesh->GetNumberOfPolys(), std::max(target, 4L));
    double volume = 0, area = 0;
    MeshVolumeAndArea(mesh, volume, area);
    if (target >= 500) {
      EXPECT_NEAR(volume, 4.0 / 3.0 * M_PI * 1000, 0.03 * 4.0 / 3.0 * M_PI * 1000) << target;
    }
  }
  // An error bound stops early.
  vtkNew<vtkPolyData> bounded;
  bounded->DeepCopy(triangles->GetOutput());
  DecimationResult r;
  ASSERT_TRUE(DecimateManifold(bounded, 4, 0.05, r));
  EXPECT_FALSE(r.TargetReached);
  EXPECT_LE(r.MaxQuadricErrorMm, 0.05);
  EXPECT_GT(bounded->GetNumberOfPolys(), 100);
  // Not a closed manifold: refused, untouched.
  vtkNew<vtkPolyData> open;
  open->DeepCopy(triangles->GetOutput());
  vtkNew<vtkCellArray> fewer;
  vtkIdType n;
  const vtkIdType* ids;
  int kept = 0;
  for (open->GetPolys()->InitTraversal(); open->GetPolys()->GetNextCell(n, ids);)
    if (kept++ > 0) fewer->InsertNextCell(n, ids);
  open->SetPolys(fewer);
  const vtkIdType before = open->GetNumberOfPolys();
  EXPECT_FALSE(DecimateManifold(open, 10, 0, r));
  EXPECT_EQ(open->GetNumberOfPolys(), before);
}

namespace {
// An octahedron (8 outward triangles on 6 corners), shifted by `offset` point ids.
std::vector<std::array<vtkIdType, 3>> Octahedron(vtkIdType offset) {
  std::vector<std::array<vtkIdType, 3>> t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (auto& tri : t)
    for (vtkIdType& id : tri) id += offset;
  return t;
}

vtkSmartPointer<vtkPolyData> Mesh(vtkIdType points, const std::vector<std::vector<vtkIdType>>& cells) {
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> p;
  for (vtkIdType i = 0; i < points; ++i) p->InsertNextPoint(static_cast<double>(i), static_cast<double>(i * i % 7), 0.0);
  mesh->SetPoints(p);
  vtkNew<vtkCellArray> polys;
  for (const auto& c : cells) polys->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  mesh->SetPolys(polys);
  return mesh;
}

std::vector<std::vector<vtkIdType>> Cells(const std::vector<std::array<vtkIdType, 3>>& triangles) {
  std::vector<std::vector<vtkIdType>> cells;
  for (const auto& t : triangles) cells.push_back({t[0], t[1], t[2]});
  return cells;
}
}  // namespace

TEST(Topology, OnePassCountsMatchKnownAnswersAndTheEdgeSort) {
  struct Case {
    const char* What;
    vtkSmartPointer<vtkPolyData> Mesh;
    long Boundary, NonManifoldEdges, NonManifoldVertices;
  };
  auto open = Octahedron(0);
  open.pop_back();  // a triangular hole: 3 boundary edges, its 3 corners' fans open
  auto bowTie = Octahedron(0);
  for (const auto& t : Octahedron(5)) bowTie.push_back(t);  // two octahedra sharing point 5
  std::vector<std::vector<vtkIdType>> fin = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};  // edge 0-1 in three
  std::vector<std::vector<vtkIdType>> quad = {{0, 1, 2, 3}};                    // not triangles
  std::vector<std::vector<vtkIdType>> degenerate = {{0, 1, 1}, {0, 1, 2}};      // a repeated corner
  const std::vector<Case> cases = {
      {"closed octahedron", Mesh(6, Cells(Octahedron(0))), 0, 0, 0},
      {"octahedron with a hole", Mesh(6, Cells(open)), 3, 0, 3},
      {"two octahedra touching at a point", Mesh(11, Cells(bowTie)), 0, 0, 1},
      {"three triangles on one edge", Mesh(5, fin), 6, 1, 5},
      {"one quad", Mesh(4, quad), 4, 0, 0},
      {"a triangle with a repeated corner", Mesh(3, degenerate), 3, 1, 3},  // edge 0-1 counted 3 times
  };
  for (const auto& c : cases) {
    const MeshTopology topology = CountTopology(c.Mesh);
    EXPECT_EQ(topology.BoundaryEdges, c.Boundary) << c.What;
    EXPECT_EQ(topology.NonManifoldEdges, c.NonManifoldEdges) << c.What;
    EXPECT_EQ(topology.NonManifoldVertices, c.NonManifoldVertices) << c.What;
    long boundary = -1, nonManifold = -1;
    CountBadEdges(c.Mesh, boundary, nonManifold);
    EXPECT_EQ(topology.BoundaryEdges, boundary) << c.What;
    EXPECT_EQ(topology.NonManifoldEdges, nonManifold) << c.What;
  }
  // A large closed mesh: the same counts as the global edge sort, in parallel chunks.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(300);
  sphere->SetPhiResolution(300);
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputConnection(sphere->GetOutputPort());
  triangulate->Update();
  const MeshTopology topology = CountTopology(triangulate->GetOutput());
  long boundary = -1, nonManifold = -1;
  CountBadEdges(triangulate->GetOutput(), boundary, nonManifold);
  EXPECT_EQ(topology.BoundaryEdges, boundary);
  EXPECT_EQ(topology.NonManifoldEdges, nonManifold);
  EXPECT_EQ(topology.NonManifoldVertices, 0);
}

// The deviation a level of detail reports is the largest vertex-to-surface distance both ways
// (every vertex when there are fewer than MaxDeviationSamples): the same number as a scan of every
// triangle, in either order of the two surfaces, and near the closed form of two offset spheres
// (radii 20 and 21 mm, centres 1.5 mm apart: 2.5 mm, less the coarse sphere's facet sagitta).
TEST(LevelOfDetail, MaxSurfaceDeviationIsTheBruteForceDistanceBothWays) {
  const TriangleMesh fine = shapes::Sphere({3, -2, 5}, 20, 4), coarse = shapes::Sphere({4.5, -2, 5}, 21, 2);
  auto oneWay = [](const TriangleMesh& from, const TriangleMesh& to) {
    double worst = 0;
    for (const Vec3& p : from.Points) {
      double best = HUGE_VAL;
      for (const auto& t : to.Triangles) {
        double bary[3];
        const Vec3 q = BVH::ClosestPointOnTriangle(p, to.Points[static_cast<size_t>(t[0])], to.Points[static_cast<size_t>(t[1])],
                                                   to.Points[static_cast<size_t>(t[2])], bary);
        best = std::min(best, Norm2(q - p));
      }
      worst = std::max(worst, best);
    }
    return std::sqrt(worst);
  };
  const double brute = std::max(oneWay(fine, coarse), oneWay(coarse, fine));
  const auto finePoly = TriangleMeshToPolyData(fine), coarsePoly = TriangleMeshToPolyData(coarse);
  EXPECT_NEAR(MaxSurfaceDeviation(finePoly, coarsePoly), brute, 1e-9);
  EXPECT_NEAR(MaxSurfaceDeviation(coarsePoly, finePoly), brute, 1e-9);
  EXPECT_NEAR(brute, 2.5, 0.5);
  EXPECT_NEAR(MaxSurfaceDeviation(finePoly, finePoly), 0.0, 1e-12);
  vtkNew<vtkPolyData> empty;
  EXPECT_EQ(MaxSurfaceDeviation(finePoly, empty), -1.0);
}
