// Makes Resources/Anatomy/KneeVHF from ../shared/data/knee-vhf-surfaces (the real right knee of the
// Visible Human Female, see that folder's README): moves the parts into the phantom's anatomy
// frame (knee joint centre at the origin, same axes), crops the long bones where the phantom's
// largest field of view ends (the femur's pose far from the knee is uncertain anyway), closes the
// cuts with flat caps, decimates only while the surface moves far less than a voxel, and writes
// each part as a .vtp (LPS with Slicer's SPACE tag, as every RoboPlan model file).
//
//   rpPrepareKneeAnatomy <knee-vhf-surfaces folder> <output folder> [--max-error mm]
//
// Prints, per part, the triangles before and after and the largest and mean deviation of the
// shipped surface from the source (vertices of each surface against the other, both ways).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkClipClosedSurface.h>
#include <vtkCleanPolyData.h>
#include <vtkFeatureEdges.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkQuadricDecimation.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>

#include "rpBVH.h"
#include "rpModelIO.h"

namespace {

struct Part {
  const char* Source;  // file in knee-vhf-surfaces
  const char* Shipped;
  double CropBelow, CropAbove;  // keep lowZ..highZ in the anatomy frame (mm); NAN: no crop
};

// The phantom's largest field of view reaches 150 mm above and below the joint; the cut is a
// little beyond it so no cap shows inside any phantom.
constexpr double kCrop = 170.0;
const Part kParts[] = {
    {"femur.vtp", "femur.vtp", NAN, kCrop},
    {"tibia.vtp", "tibia.vtp", -kCrop, NAN},
    {"fibula.vtp", "fibula.vtp", -kCrop, NAN},
    {"patella.vtp", "patella.vtp", NAN, NAN},
    {"cartilage_femur.vtp", "cartilage_femur.vtp", NAN, NAN},
    {"cartilage_tibia_medial.vtp", "cartilage_tibia_medial.vtp", NAN, NAN},
    {"cartilage_tibia_lateral.vtp", "cartilage_tibia_lateral.vtp", NAN, NAN},
    {"cartilage_patella.vtp", "cartilage_patella.vtp", NAN, NAN},
    {"ligament_acl.vtp", "ligament_acl.vtp", NAN, NAN},
    {"ligament_pcl.vtp", "ligament_pcl.vtp", NAN, NAN},
    {"ligament_mcl.vtp", "ligament_mcl.vtp", NAN, NAN},
    {"ligament_lcl.vtp", "ligament_lcl.vtp", NAN, NAN},
};

vtkSmartPointer<vtkPolyData> Read(const std::string& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetErrorCode() != 0 || reader->GetOutput()->GetNumberOfPoints() == 0) {
    std::fprintf(stderr, "cannot read '%s'\n", path.c_str());
    std::exit(1);
  }
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(reader->GetOutputPort());
  triangles->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(triangles->GetOutput());
  return out;
}

rp::TriangleMesh ToMesh(vtkPolyData* poly) {
  rp::TriangleMesh mesh;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    mesh.Points.push_back({p[0], p[1], p[2]});
  }
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = poly->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
    if (n == 3) mesh.Triangles.push_back({int32_t(ids[0]), int32_t(ids[1]), int32_t(ids[2])});
  return mesh;
}

struct Deviation {
  double Max = 0, Mean = 0;
};
// Vertices of `from` against the surface of `to`, limited to the z range [lo, hi].
Deviation VertexDistances(vtkPolyData* from, const rp::BVH& to, double lo, double hi) {
  Deviation d;
  long n = 0;
  for (vtkIdType i = 0; i < from->GetNumberOfPoints(); ++i) {
    double p[3];
    from->GetPoint(i, p);
    if (p[2] < lo || p[2] > hi) continue;
    rp::ClosestPointHit hit;
    if (!to.ClosestPoint({p[0], p[1], p[2]}, 1e9, hit)) continue;
    const double e = std::sqrt(hit.Distance2);
    d.Max = std::max(d.Max, e);
    d.Mean += e;
    ++n;
  }
  if (n) d.Mean /= n;
  return d;
}

void Topology(vtkPolyData* poly, long& boundary, long& nonManifold, long& pieces) {
  vtkNew<vtkFeatureEdges> edges;
  edges->SetInputData(poly);
  edges->BoundaryEdgesOn();
  edges->NonManifoldEdgesOff();
  edges->FeatureEdgesOff();
  edges->ManifoldEdgesOff();
  edges->Update();
  boundary = edges->GetOutput()->GetNumberOfCells();
  edges->BoundaryEdgesOff();
  edges->NonManifoldEdgesOn();
  edges->Update();
  nonManifold = edges->GetOutput()->GetNumberOfCells();
  vtkNew<vtkPolyDataConnectivityFilter> connectivity;
  connectivity->SetInputData(poly);
  connectivity->SetExtractionModeToAllRegions();
  connectivity->Update();
  pieces = connectivity->GetNumberOfExtractedRegions();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: rpPrepareKneeAnatomy <knee-vhf-surfaces folder> <output folder> [--max-error mm]\n");
    return 2;
  }
  const std::string in = argv[1], out = argv[2];
  double maxError = 0.05;  // mm: a sixth of the finest phantom voxel (0.3 mm)
  if (argc >= 5 && std::string(argv[3]) == "--max-error") maxError = std::atof(argv[4]);

  // The anatomy frame: the source frame moved so the knee joint centre is the origin. x, y from
  // the middle of the two tibial cartilages, z half-way between the lowest point of the femur and
  // the highest point of the tibia (the joint space).
  double cart[6] = {1e9, -1e9, 1e9, -1e9, 1e9, -1e9}, femur[6], tibia[6];
  for (const char* name : {"cartilage_tibia_medial.vtp", "cartilage_tibia_lateral.vtp"}) {
    double b[6];
    Read(in + "/" + name)->GetBounds(b);
    for (int a = 0; a < 3; ++a) cart[2 * a] = std::min(cart[2 * a], b[2 * a]), cart[2 * a + 1] = std::max(cart[2 * a + 1], b[2 * a + 1]);
  }
  Read(in + "/femur.vtp")->GetBounds(femur);
  Read(in + "/tibia.vtp")->GetBounds(tibia);
  // Rounded to 0.1 mm so the offset can be written down exactly.
  const double centre[3] = {std::round(5 * (cart[0] + cart[1])) / 10, std::round(5 * (cart[2] + cart[3])) / 10,
                            std::round(5 * (femur[4] + tibia[5])) / 10};
  std::printf("anatomy frame = source frame - (%.1f, %.1f, %.1f) mm\n", centre[0], centre[1], centre[2]);
  vtkNew<vtkTransform> shift;
  shift->Translate(-centre[0], -centre[1], -centre[2]);
  {
    // The frame change, written as the source folder writes its own (4x4, row by row).
    FILE* frame = std::fopen((out + "/knee-vhf-surfaces_to_this_frame_4x4.txt").c_str(), "w");
    if (!frame) {
      std::fprintf(stderr, "cannot write into '%s'\n", out.c_str());
      return 1;
    }
    std::fprintf(frame, "1.000000 0.000000 0.000000 %.6f\n0.000000 1.000000 0.000000 %.6f\n"
                        "0.000000 0.000000 1.000000 %.6f\n0.000000 0.000000 0.000000 1.000000\n",
                 -centre[0], -centre[1], -centre[2]);
    std::fclose(frame);
  }

  std::printf("%-28s %9s %9s %9s %10s %10s  %s\n", "part", "source", "cropped", "shipped", "max dev", "mean dev",
              "topology");
  for (const Part& part : kParts) {
    vtkNew<vtkTransformPolyDataFilter> moved;
    moved->SetTransform(shift);
    moved->SetInputData(Read(in + "/" + part.Source));
    moved->Update();
    vtkSmartPointer<vtkPolyData> source = moved->GetOutput();
    const vtkIdType sourceTriangles = source->GetNumberOfCells();
    vtkSmartPointer<vtkPolyData> cropped = source;
    if (!std::isnan(part.CropBelow) || !std::isnan(part.CropAbove)) {
      vtkNew<vtkPlaneCollection> planes;
      if (!std::isnan(part.CropAbove)) {
        vtkNew<vtkPlane> plane;
        plane->SetOrigin(0, 0, part.CropAbove);
        plane->SetNormal(0, 0, -1);  // keeps z < CropAbove
        planes->AddItem(plane);
      }
      if (!std::isnan(part.CropBelow)) {
        vtkNew<vtkPlane> plane;
        plane->SetOrigin(0, 0, part.CropBelow);
        plane->SetNormal(0, 0, 1);
        planes->AddItem(plane);
      }
      vtkNew<vtkClipClosedSurface> clip;
      clip->SetInputData(source);
      clip->SetClippingPlanes(planes);
      clip->SetGenerateFaces(1);
      vtkNew<vtkTriangleFilter> triangles;
      triangles->SetInputConnection(clip->GetOutputPort());
      vtkNew<vtkCleanPolyData> clean;
      clean->SetInputConnection(triangles->GetOutputPort());
      clean->Update();
      cropped = clean->GetOutput();
    }
    const double lo = std::isnan(part.CropBelow) ? -1e9 : part.CropBelow + 1.0;
    const double hi = std::isnan(part.CropAbove) ? 1e9 : part.CropAbove - 1.0;
    rp::BVH sourceTree;
    sourceTree.Build(ToMesh(source));

    // The strongest decimation whose surface stays within maxError of the source, closed and
    // manifold in one piece.
    vtkSmartPointer<vtkPolyData> shipped = cropped;
    Deviation shippedDeviation;
    for (double reduction : {0.9, 0.85, 0.8, 0.75, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1}) {
      vtkNew<vtkQuadricDecimation> decimate;
      decimate->SetInputData(cropped);
      decimate->SetTargetReduction(reduction);
      decimate->VolumePreservationOn();
      decimate->Update();
      vtkPolyData* candidate = decimate->GetOutput();
      long boundary, nonManifold, pieces;
      Topology(candidate, boundary, nonManifold, pieces);
      if (boundary || nonManifold || pieces != 1) continue;
      rp::BVH candidateTree;
      candidateTree.Build(ToMesh(candidate));
      const Deviation a = VertexDistances(candidate, sourceTree, lo, hi);
      const Deviation b = VertexDistances(source, candidateTree, lo, hi);
      if (std::max(a.Max, b.Max) > maxError) continue;
      shipped = vtkSmartPointer<vtkPolyData>::New();
      shipped->ShallowCopy(candidate);
      shippedDeviation = {std::max(a.Max, b.Max), 0.5 * (a.Mean + b.Mean)};
      break;
    }
    if (shipped == cropped) {
      rp::BVH croppedTree;
      croppedTree.Build(ToMesh(cropped));
      const Deviation b = VertexDistances(source, croppedTree, lo, hi);
      shippedDeviation = {b.Max, b.Mean};
    }
    // Only points and triangles are shipped (no normals or other arrays).
    vtkNew<vtkPolyData> bare;
    bare->SetPoints(shipped->GetPoints());
    bare->SetPolys(shipped->GetPolys());
    long boundary, nonManifold, pieces;
    Topology(bare, boundary, nonManifold, pieces);
    std::string error;
    if (!rp::WriteModelFile(out + "/" + part.Shipped, bare, error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
    double b[6];
    bare->GetBounds(b);
    std::printf("%-28s %9lld %9lld %9lld %7.3f mm %7.3f mm  %ld boundary, %ld non-manifold edges, %ld piece(s); "
                "x %.0f..%.0f y %.0f..%.0f z %.0f..%.0f\n",
                part.Shipped, static_cast<long long>(sourceTriangles), static_cast<long long>(cropped->GetNumberOfCells()),
                static_cast<long long>(bare->GetNumberOfCells()), shippedDeviation.Max, shippedDeviation.Mean, boundary,
                nonManifold, pieces, b[0], b[1], b[2], b[3], b[4], b[5]);
  }
  return 0;
}
