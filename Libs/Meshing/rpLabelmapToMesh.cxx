#include "rpLabelmapToMesh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include <vtkAOSDataArrayTemplate.h>
#include <vtkCellArray.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include "rpManifoldDecimation.h"

namespace rp {

bool ParseMeshMethod(const std::string& text, MeshMethod& method) {
  if (text == "gaussian") method = MeshMethod::Gaussian;
  else if (text == "sinc") method = MeshMethod::WindowedSinc;
  else if (text == "slicer") method = MeshMethod::SlicerDefault;
  else if (text == "discrete" || text == "none") method = MeshMethod::Discrete;
  else return false;
  return true;
}

const char* MeshMethodName(MeshMethod method) {
  switch (method) {
    case MeshMethod::Gaussian: return "gaussian";
    case MeshMethod::WindowedSinc: return "sinc";
    case MeshMethod::SlicerDefault: return "slicer";
    case MeshMethod::Discrete: return "discrete";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

// How far from the 0.5 level the constraint puts voxel-centre samples (see GaussianResample).
constexpr float ConstraintMargin = 0.01f;

struct LabelBounds {
  int Lo[3] = {0, 0, 0}, Hi[3] = {-1, -1, -1};
  long Count = 0;
  bool Empty() const { return this->Count == 0; }
};

template <typename T>
void FindBounds(const T* voxels, const int dims[3], long label, LabelBounds& b) {
  const T value = static_cast<T>(label);
  struct Local {
    int Lo[3] = {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
    int Hi[3] = {-1, -1, -1};
    long Count = 0;
  };
  vtkSMPThreadLocal<Local> locals;
  vtkSMPTools::For(0, dims[2], [&](vtkIdType k0, vtkIdType k1) {
    Local& l = locals.Local();
    for (vtkIdType kk = k0; kk < k1; ++kk) {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < dims[1]; ++j) {
        const T* row = voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
        // Count first (a branch-free loop the compiler vectorizes), then find the ends only in
        // rows that hold the label: most rows of a large labelmap do not.
        long count = 0;
        for (int i = 0; i < dims[0]; ++i) count += row[i] == value;
        if (count == 0) continue;
        l.Count += count;
        int first = 0, last = dims[0] - 1;
        while (row[first] != value) ++first;
        while (row[last] != value) --last;
        l.Lo[0] = std::min(l.Lo[0], first), l.Hi[0] = std::max(l.Hi[0], last);
        l.Lo[1] = std::min(l.Lo[1], j), l.Hi[1] = std::max(l.Hi[1], j);
        l.Lo[2] = std::min(l.Lo[2], k), l.Hi[2] = std::max(l.Hi[2], k);
      }
    }
  });
  LabelBounds result;
  for (int a = 0; a < 3; ++a) result.Lo[a] = std::numeric_limits<int>::max(), result.Hi[a] = -1;
  for (const Local& l : locals) {
    result.Count += l.Count;
    for (int a = 0; a < 3; ++a) result.Lo[a] = std::min(result.Lo[a], l.Lo[a]), result.Hi[a] = std::max(result.Hi[a], l.Hi[a]);
  }
  b = result;
}

// A label's bounds, scanned once per labelmap version: a level of detail contours the same label
// on several grids, and each scan reads the whole volume (78 M voxels for 512x512x300).
// Per thread, so no lock; keyed by the image and its modification time (VTK's global counter).
LabelBounds CachedBounds(vtkImageData* labelmap, const int dims[3], long label) {
  struct Entry {
    const void* Image = nullptr;
    vtkMTimeType Time = 0;
    long Label = 0;
    LabelBounds Bounds;
  };
  thread_local std::array<Entry, 8> cache;
  thread_local size_t next = 0;
  const vtkMTimeType time = std::max(labelmap->GetMTime(), labelmap->GetPointData()->GetScalars()->GetMTime());
  for (const Entry& e : cache)
    if (e.Image == labelmap && e.Time == time && e.Label == label) return e.Bounds;
  Entry& e = cache[next++ % cache.size()];
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(FindBounds(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims, label, e.Bounds));
  }
  e.Image = labelmap, e.Time = time, e.Label = label;
  return e.Bounds;
}

bool IntegerScalars(vtkImageData* image) {
  switch (image->GetScalarType()) {
    case VTK_UNSIGNED_CHAR: case VTK_SIGNED_CHAR: case VTK_CHAR: case VTK_SHORT: case VTK_UNSIGNED_SHORT:
    case VTK_INT: case VTK_UNSIGNED_INT: case VTK_LONG: case VTK_UNSIGNED_LONG: case VTK_LONG_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      return true;
    default:
      return false;
  }
}

// Binary mask (1 = label) of the crop box [lo - pad, hi + pad] (voxels outside the image are 0).
template <typename T>
void ExtractMask(const T* voxels, const int dims[3], long label, const int start[3], const int size[3],
                 unsigned char* mask) {
  const T value = static_cast<T>(label);
  vtkSMPTools::For(0, size[2], [&](vtkIdType k0, vtkIdType k1) {
    for (vtkIdType kk = k0; kk < k1; ++kk) {
      const int k = start[2] + static_cast<int>(kk);
      for (int jj = 0; jj < size[1]; ++jj) {
        unsigned char* out = mask + (static_cast<size_t>(kk) * size[1] + jj) * size[0];
        const int j = start[1] + jj;
        if (k < 0 || k >= dims[2] || j < 0 || j >= dims[1]) {
          std::fill(out, out + size[0], 0);
          continue;
        }
        const T* row = voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
        for (int ii = 0; ii < size[0]; ++ii) {
          const int i = start[0] + ii;
          out[ii] = (i >= 0 && i < dims[0] && row[i] == value) ? 1 : 0;
        }
      }
    }
  });
}

// 1-D resampling weights: output o sits at input position start + o * step.
struct Kernel1D {
  std::vector<int> First, Count;   // first input index (relative to the input range) and tap count
  std::vector<size_t> Offset;      // into Weights
  std::vector<float> Weights;
};

Kernel1D MakeKernel(double start, double step, int outputCount, int inputCount, double sigma) {
  Kernel1D kernel;
  const double radius = 3.0 * sigma;
  for (int o = 0; o < outputCount; ++o) {
    const double p = start + o * step;
    const int k0 = static_cast<int>(std::ceil(p - radius)), k1 = static_cast<int>(std::floor(p + radius));
    double norm = 0;
    for (int k = k0; k <= k1; ++k) norm += std::exp(-0.5 * (p - k) * (p - k) / (sigma * sigma));
    const int first = std::max(k0, 0), last = std::min(k1, inputCount - 1);
    kernel.First.push_back(first);
    kernel.Count.push_back(std::max(0, last - first + 1));
    kernel.Offset.push_back(kernel.Weights.size());
    for (int k = first; k <= last; ++k) {
      kernel.Weights.push_back(static_cast<float>(std::exp(-0.5 * (p - k) * (p - k) / (sigma * sigma)) / norm));
    }
  }
  return kernel;
}

// Separable Gaussian resampling of the bounding box of `label` onto the contour grid.
// Input range per axis = the label's bounds (the mask is zero elsewhere).
template <typename T>
void GaussianResample(const T* voxels, const int dims[3], long label, const LabelBounds& b, const double gridStart[3],
                      const double step[3], const int outDims[3], const double sigma[3], float* field) {
  const T value = static_cast<T>(label);
  int inDims[3];
  for (int a = 0; a < 3; ++a) inDims[a] = b.Hi[a] - b.Lo[a] + 1;
  Kernel1D kx = MakeKernel(gridStart[0] - b.Lo[0], step[0], outDims[0], inDims[0], sigma[0]);
  Kernel1D ky = MakeKernel(gridStart[1] - b.Lo[1], step[1], outDims[1], inDims[1], sigma[1]);
  Kernel1D kz = MakeKernel(gridStart[2] - b.Lo[2], step[2], outDims[2], inDims[2], sigma[2]);

  // Passes x and y, one input slice at a time: mask rows → A[outX x inY] (a buffer per thread,
  // small enough to stay in cache) → B[outX x outY x inZ]. B is left uninitialized (every value
  // is written below): zeroing it first took a serial pass over tens of MB.
  const size_t nxo = static_cast<size_t>(outDims[0]);
  const size_t nyo = static_cast<size_t>(outDims[1]);
  std::unique_ptr<float[]> B(new float[nxo * nyo * static_cast<size_t>(inDims[2])]);
  vtkSMPThreadLocal<std::vector<float>> sliceA;
  vtkSMPTools::For(0, inDims[2], [&](vtkIdType k0, vtkIdType k1) {
    std::vector<float>& A = sliceA.Local();
    A.resize(nxo * static_cast<size_t>(inDims[1]));
    std::vector<float> row(static_cast<size_t>(inDims[0]));
    for (vtkIdType kk = k0; kk < k1; ++kk) {
      for (int jj = 0; jj < inDims[1]; ++jj) {
        const T* in = voxels + (static_cast<size_t>(b.Lo[2] + kk) * dims[1] + (b.Lo[1] + jj)) * dims[0] + b.Lo[0];
        bool any = false;
        for (int i = 0; i < inDims[0]; ++i) {
          row[static_cast<size_t>(i)] = in[i] == value ? 1.0f : 0.0f;
          any = any || in[i] == value;
        }
        float* out = A.data() + static_cast<size_t>(jj) * nxo;
        if (!any) {
          std::fill(out, out + nxo, 0.0f);
          continue;
        }
        for (size_t o = 0; o < nxo; ++o) {
          const float* w = kx.Weights.data() + kx.Offset[o];
          const float* x = row.data() + kx.First[o];
          float sum = 0;
          for (int t = 0; t < kx.Count[o]; ++t) sum += w[t] * x[t];
          out[o] = sum;
        }
      }
      for (size_t oy = 0; oy < nyo; ++oy) {
        float* out = B.get() + (static_cast<size_t>(kk) * nyo + oy) * nxo;
        std::fill(out, out + nxo, 0.0f);
        const float* w = ky.Weights.data() + ky.Offset[oy];
        for (int t = 0; t < ky.Count[oy]; ++t) {
          const float* in = A.data() + static_cast<size_t>(ky.First[oy] + t) * nxo;
          const float wt = w[t];
          for (size_t x = 0; x < nxo; ++x) out[x] += wt * in[x];
        }
      }
    }
  });
  // Pass z: B → field[outX x outY x outZ].
  const size_t plane = nxo * nyo;
  vtkSMPTools::For(0, outDims[2], [&](vtkIdType z0, vtkIdType z1) {
    for (vtkIdType oz = z0; oz < z1; ++oz) {
      float* out = field + static_cast<size_t>(oz) * plane;
      std::fill(out, out + plane, 0.0f);
      const float* w = kz.Weights.data() + kz.Offset[static_cast<size_t>(oz)];
      for (int t = 0; t < kz.Count[static_cast<size_t>(oz)]; ++t) {
        const float* in = B.get() + static_cast<size_t>(kz.First[static_cast<size_t>(oz)] + t) * plane;
        const float wt = w[t];
        for (size_t x = 0; x < plane; ++x) out[x] += wt * in[x];
      }
    }
  });
  // Constrain the field at samples that sit on voxel centres: labelled voxels stay inside the
  // surface, others outside. The blur smooths staircases; the constraint keeps one-voxel
  // structures (a single voxel, a one-voxel-thin plate) that a blur alone would erase.
  auto onCentre = [](double p) { return std::abs(p - std::round(p)) < 1e-6; };
  constexpr int NotCentre = std::numeric_limits<int>::min();
  std::vector<int> centre[3];
  for (int a = 0; a < 3; ++a) {
    centre[a].assign(static_cast<size_t>(outDims[a]), NotCentre);
    for (int o = 0; o < outDims[a]; ++o) {
      const double p = gridStart[a] + o * step[a];
      if (onCentre(p)) centre[a][static_cast<size_t>(o)] = static_cast<int>(std::lround(p));
    }
  }
  const float high = 0.5f + ConstraintMargin, low = 0.5f - ConstraintMargin;
  vtkSMPTools::For(0, outDims[2], [&](vtkIdType z0, vtkIdType z1) {
    for (vtkIdType oz = z0; oz < z1; ++oz) {
      const int k = centre[2][static_cast<size_t>(oz)];
      if (k == NotCentre) continue;
      for (int oy = 0; oy < outDims[1]; ++oy) {
        const int j = centre[1][static_cast<size_t>(oy)];
        if (j == NotCentre) continue;
        float* out = field + static_cast<size_t>(oz) * plane + static_cast<size_t>(oy) * nxo;
        const bool rowInside = k >= 0 && k < dims[2] && j >= 0 && j < dims[1];
        const T* row = rowInside ? voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0] : nullptr;
        for (size_t ox = 0; ox < nxo; ++ox) {
          const int i = centre[0][ox];
          if (i == NotCentre) continue;
          const bool inside = row && i >= 0 && i < dims[0] && row[i] == value;
          out[ox] = inside ? std::max(out[ox], high) : std::min(out[ox], low);
        }
      }
    }
  });
}

// Points (grid index p) → RAS: ras = M * (start + p * step). Normals given as gradients in grid
// coordinates (may be null) go through the inverse transpose and are normalized.
void GridToRAS(vtkPolyData* mesh, const vtkMatrix4x4* ijkToRAS, const double start[3], const double step[3],
               bool haveGridNormals) {
  double m[3][4], nm[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = ijkToRAS->GetElement(r, c);
  vtkNew<vtkMatrix4x4> inverse;
  vtkMatrix4x4::Invert(const_cast<vtkMatrix4x4*>(ijkToRAS), inverse);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) nm[r][c] = inverse->GetElement(c, r) / step[c];  // (M^-T) * diag(1/step)
  vtkPoints* points = mesh->GetPoints();
  vtkDataArray* normals = haveGridNormals ? mesh->GetPointData()->GetNormals() : nullptr;
  vtkSMPTools::For(0, mesh->GetNumberOfPoints(), [&](vtkIdType p0, vtkIdType p1) {
    double p[3], q[3], n[3];
    for (vtkIdType id = p0; id < p1; ++id) {
      points->GetPoint(id, p);
      for (int a = 0; a < 3; ++a) p[a] = start[a] + p[a] * step[a];
      for (int r = 0; r < 3; ++r) q[r] = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
      points->SetPoint(id, q);
      if (!normals) continue;
      normals->GetTuple(id, p);
      for (int r = 0; r < 3; ++r) n[r] = nm[r][0] * p[0] + nm[r][1] * p[1] + nm[r][2] * p[2];
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0) n[0] /= len, n[1] /= len, n[2] /= len;
      normals->SetTuple(id, n);
    }
  });
}

// Points read without a virtual call per coordinate (float or double storage; else vtkPoints).
struct PointsView {
  explicit PointsView(vtkPoints* points) : Points(points) {
    vtkDataArray* data = points->GetData();
    if (auto* f = vtkAOSDataArrayTemplate<float>::FastDownCast(data)) this->F = f->GetPointer(0);
    else if (auto* d = vtkAOSDataArrayTemplate<double>::FastDownCast(data)) this->D = d->GetPointer(0);
  }
  void Get(vtkIdType i, double x[3]) const {
    if (this->F) {
      const float* p = this->F + 3 * i;
      x[0] = p[0], x[1] = p[1], x[2] = p[2];
    } else if (this->D) {
      const double* p = this->D + 3 * i;
      x[0] = p[0], x[1] = p[1], x[2] = p[2];
    } else {
      this->Points->GetPoint(i, x);
    }
  }
  vtkPoints* Points;
  float* F = nullptr;
  double* D = nullptr;
};

// Area-weighted vertex normals (outward for an outward-oriented mesh).
void ComputeVertexNormals(vtkPolyData* mesh) {
  const vtkIdType np = mesh->GetNumberOfPoints();
  std::vector<double> acc(static_cast<size_t>(np) * 3, 0.0);
  ForEachTriangle(mesh, [&](const vtkIdType* ids, const double*, const double*, const double*, const double* f) {
    for (int t = 0; t < 3; ++t)
      for (int d = 0; d < 3; ++d) acc[static_cast<size_t>(ids[t]) * 3 + d] += f[d];
  });
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(np);
  for (vtkIdType id = 0; id < np; ++id) {
    double* v = &acc[static_cast<size_t>(id) * 3];
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0) v[0] /= len, v[1] /= len, v[2] /= len;
    normals->SetTuple(id, v);
  }
  mesh->GetPointData()->SetNormals(normals);
}

// Makes triangles and normals point outward (positive enclosed volume).
void OrientOutward(vtkPolyData* mesh) {
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  if (volume < 0) {
    vtkCellArray* polys = mesh->GetPolys();
    vtkNew<vtkCellArray> flipped;
    flipped->AllocateExact(polys->GetNumberOfCells(), polys->GetNumberOfConnectivityIds());
    vtkIdType n;
    const vtkIdType* ids;
    std::vector<vtkIdType> reversed;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
      reversed.assign(ids, ids + n);
      std::reverse(reversed.begin(), reversed.end());
      flipped->InsertNextCell(n, reversed.data());
    }
    mesh->SetPolys(flipped);
  }
  // Normals must agree with the (now outward) triangles: compare with face normals in bulk.
  vtkDataArray* normals = mesh->GetPointData()->GetNormals();
  if (!normals) return;
  double agreement = 0, nv[3];
  ForEachTriangle(mesh, [&](const vtkIdType* ids, const double*, const double*, const double*, const double* f) {
    normals->GetTuple(ids[0], nv);
    agreement += f[0] * nv[0] + f[1] * nv[1] + f[2] * nv[2];
  });
  if (agreement < 0) {
    for (vtkIdType id = 0; id < normals->GetNumberOfTuples(); ++id) {
      normals->GetTuple(id, nv);
      nv[0] = -nv[0], nv[1] = -nv[1], nv[2] = -nv[2];
      normals->SetTuple(id, nv);
    }
  }
}

// Moves vertices along their normals so the enclosed volume becomes `targetVolume`. The
// first-order offset (dV / area) misses the curvature term, so it iterates a few times.
double CorrectVolume(vtkPolyData* mesh, double targetVolume) {
  double volume = 0, area = 0;
  MeshVolumeAndArea(mesh, volume, area);
  vtkDataArray* normals = mesh->GetPointData()->GetNormals();
  if (area <= 0 || !normals) return 0;
  double total = 0;
  for (int pass = 0; pass < 8 && std::abs(targetVolume - volume) > 1e-5 * targetVolume; ++pass) {
    const double offset = (targetVolume - volume) / area;
    vtkPoints* points = mesh->GetPoints();
    const PointsView view(points);
    vtkSMPTools::For(0, mesh->GetNumberOfPoints(), [&](vtkIdType b, vtkIdType e) {
      double p[3], n[3];
      for (vtkIdType id = b; id < e; ++id) {
        normals->GetTuple(id, n);
        if (view.F) {
          for (int a = 0; a < 3; ++a) view.F[3 * id + a] += static_cast<float>(offset * n[a]);
        } else if (view.D) {
          for (int a = 0; a < 3; ++a) view.D[3 * id + a] += offset * n[a];
        } else {
          view.Get(id, p);
          for (int a = 0; a < 3; ++a) p[a] += offset * n[a];
          points->SetPoint(id, p);
        }
      }
    });
    points->Modified();
    total += offset;
    MeshVolumeAndArea(mesh, volume, area);
  }
  return total;
}

void FillStats(vtkPolyData* mesh, MeshStats& stats) {
  stats.Triangles = mesh->GetNumberOfPolys();
  stats.Points = mesh->GetNumberOfPoints();
  MeshVolumeAndArea(mesh, stats.MeshVolumeMm3, stats.AreaMm2);
  stats.VolumeErrorPercent =
      stats.LabelVolumeMm3 > 0 ? 100.0 * (stats.MeshVolumeMm3 - stats.LabelVolumeMm3) / stats.LabelVolumeMm3 : 0.0;
  const MeshTopology topology = CountTopology(mesh);
  stats.BoundaryEdges = topology.BoundaryEdges;
  stats.NonManifoldEdges = topology.NonManifoldEdges;
  stats.NonManifoldVertices = topology.NonManifoldVertices;
  stats.Watertight = stats.Triangles > 0 && stats.BoundaryEdges == 0 && stats.NonManifoldEdges == 0;
  stats.Manifold = stats.Watertight && stats.NonManifoldVertices == 0;
}

double Determinant3(const vtkMatrix4x4* m) {
  double a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = m->GetElement(r, c);
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

bool GaussianMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const LabelBounds& b,
                  const MeshOptions& options, vtkPolyData* output, MeshStats& stats, std::string& error,
                  const ProgressCallback& progress) {
  int dims[3];
  labelmap->GetDimensions(dims);
  double sigma[3], start[3], step[3];
  int outDims[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = std::max(0.25, options.GridStep[a]);
    sigma[a] = std::max({options.Sigma, 0.4 * step[a], 0.2});
    const double pad = std::ceil(3.0 * sigma[a]) + step[a];
    start[a] = b.Lo[a] - pad;
    outDims[a] = static_cast<int>(std::ceil((b.Hi[a] + pad - start[a]) / step[a])) + 1;
    stats.GridStep[a] = step[a];
  }
  const double cells = static_cast<double>(outDims[0]) * outDims[1] * outDims[2];
  if (cells > 1.5e9) {
    error = "contour grid of " + std::to_string(static_cast<long long>(cells)) + " samples is too large; raise the grid step";
    return false;
  }
  if (progress) progress(0.1, "resampling");
  vtkNew<vtkImageData> field;
  field->SetDimensions(outDims);
  field->AllocateScalars(VTK_FLOAT, 1);
  float* f = static_cast<float*>(field->GetScalarPointer());
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(GaussianResample(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims, label, b, start,
                                      step, outDims, sigma, f));
  }
  if (progress) progress(0.4, "contouring");
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(field);
  contour->SetValue(0, 0.5);
  contour->ComputeNormalsOn();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  output->ShallowCopy(contour->GetOutput());
  if (output->GetNumberOfPolys() == 0) {
    error = "the smoothed segment has no surface at the 0.5 level (structures thinner than the smoothing; "
            "lower the smoothing or the grid step)";
    return false;
  }
  if (progress) progress(0.7, "mapping to RAS");
  GridToRAS(output, ijkToRAS, start, step, true);
  OrientOutward(output);
  return true;
}

bool DiscreteMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const LabelBounds& b,
                  const MeshOptions& options, vtkPolyData* output, MeshStats& stats, std::string& error,
                  const ProgressCallback& progress) {
  int dims[3], start[3], size[3];
  labelmap->GetDimensions(dims);
  for (int a = 0; a < 3; ++a) {
    start[a] = b.Lo[a] - 1;
    size[a] = b.Hi[a] - b.Lo[a] + 3;
  }
  vtkNew<vtkImageData> mask;
  mask->SetDimensions(size);
  mask->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(ExtractMask(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims, label, start, size,
                                 static_cast<unsigned char*>(mask->GetScalarPointer())));
  }
  if (progress) progress(0.2, "contouring");
  vtkNew<vtkDiscreteFlyingEdges3D> contour;
  contour->SetInputData(mask);
  contour->SetValue(0, 1);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkSmartPointer<vtkPolyData> mesh = contour->GetOutput();
  if (mesh->GetNumberOfPolys() == 0) {
    error = "discrete contouring gave no triangles";
    return false;
  }
  if (options.Method == MeshMethod::WindowedSinc || options.Method == MeshMethod::SlicerDefault) {
    if (progress) progress(0.4, "smoothing");
    vtkNew<vtkWindowedSincPolyDataFilter> smoother;
    smoother->SetInputData(mesh);
    smoother->SetNumberOfIterations(options.SincIterations);
    smoother->SetPassBand(options.SincPassBand);
    smoother->BoundarySmoothingOff();
    smoother->FeatureEdgeSmoothingOff();
    smoother->NonManifoldSmoothingOn();
    smoother->NormalizeCoordinatesOn();
    smoother->Update();
    // On tiny meshes (a few voxels) the sinc filter can collapse or explode the surface.
    double before = 0, after = 0, area = 0;
    MeshVolumeAndArea(mesh, before, area);
    MeshVolumeAndArea(smoother->GetOutput(), after, area);
    if (std::isfinite(after) && std::abs(after) > 0.5 * std::abs(before) && std::abs(after) < 2.0 * std::abs(before)) {
      mesh = smoother->GetOutput();
    } else {
      stats.Warnings.push_back("windowed sinc collapsed the surface (too few voxels): kept the unsmoothed surface");
    }
  }
  output->ShallowCopy(mesh);
  // Own the points before moving them (the filter output may share them).
  vtkNew<vtkPoints> points;
  points->DeepCopy(mesh->GetPoints());
  output->SetPoints(points);
  const double origin[3] = {static_cast<double>(start[0]), static_cast<double>(start[1]), static_cast<double>(start[2])};
  const double unit[3] = {1, 1, 1};
  if (progress) progress(0.7, "mapping to RAS");
  GridToRAS(output, ijkToRAS, origin, unit, false);
  if (options.Method == MeshMethod::SlicerDefault) {
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(output);
    normals->ConsistencyOn();
    normals->SplittingOff();
    normals->Update();
    output->ShallowCopy(normals->GetOutput());
  } else {
    OrientOutward(output);
    ComputeVertexNormals(output);
  }
  return true;
}

// Sorted edge keys, one per use of an edge by a triangle: a run of one is a boundary edge, a run
// of more than two a non-manifold edge.
template <typename Key>
void CountEdgeUses(const std::vector<Key>& sorted, long& boundary, long& nonManifold) {
  for (size_t i = 0; i < sorted.size();) {
    size_t j = i + 1;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    if (j - i == 1) ++boundary;
    else if (j - i > 2) ++nonManifold;
    i = j;
  }
}

void Decimate(vtkPolyData* mesh, double fraction, MeshStats& stats) {
  if (fraction <= 0) return;
  DecimationResult result;
  const long target = static_cast<long>(std::ceil((1.0 - std::min(fraction, 0.99)) * mesh->GetNumberOfPolys()));
  if (!DecimateManifold(mesh, target, 0.0, result)) {
    stats.Warnings.push_back("decimation skipped: the mesh is not a closed manifold");
    return;
  }
  ComputeVertexNormals(mesh);
  stats.Method += ", edge collapse";
}

}  // namespace

void CountBadEdges(vtkPolyData* mesh, long& boundaryEdges, long& nonManifoldEdges) {
  boundaryEdges = nonManifoldEdges = 0;
  // Every edge key once per triangle side, sorted: a run of 2 is a manifold edge.
  std::vector<uint64_t> edges;
  edges.reserve(static_cast<size_t>(mesh->GetPolys()->GetNumberOfConnectivityIds()));
  vtkCellArray* polys = mesh->GetPolys();
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    for (vtkIdType e = 0; e < n; ++e) {
      uint64_t a = static_cast<uint64_t>(ids[e]), c = static_cast<uint64_t>(ids[(e + 1) % n]);
      if (a > c) std::swap(a, c);
      edges.push_back((a << 32) | c);
    }
  }
  vtkSMPTools::Sort(edges.begin(), edges.end());
  CountEdgeUses(edges, boundaryEdges, nonManifoldEdges);
}

long CountNonManifoldVertices(vtkPolyData* mesh) { return CountTopology(mesh).NonManifoldVertices; }

MeshTopology CountTopology(vtkPolyData* mesh) {
  // Per vertex, the edges opposite it in its triangles (its link): a closed fan is one cycle, and
  // edge (v, w) lies in as many triangles as v's link has edges ending at w.
  const vtkIdType np = mesh->GetNumberOfPoints();
  vtkCellArray* polys = mesh->GetPolys();
  std::vector<vtkIdType> start(static_cast<size_t>(np) + 1, 0);
  bool triangles = true;  // only triangles with three different corners: else edges the general way
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
    if (n != 3 || ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) triangles = false;
    if (n == 3)
      for (int k = 0; k < 3; ++k) ++start[static_cast<size_t>(ids[k]) + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<std::array<vtkIdType, 2>> link(static_cast<size_t>(start.back()));
  std::vector<vtkIdType> fill(start.begin(), start.end() - 1);
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
    if (n == 3)
      for (int k = 0; k < 3; ++k) link[static_cast<size_t>(fill[static_cast<size_t>(ids[k])]++)] = {ids[(k + 1) % 3], ids[(k + 2) % 3]};
  std::atomic<long> badVertices{0}, boundaryEdges{0}, nonManifoldEdges{0};
  vtkSMPTools::For(0, np, [&](vtkIdType v0, vtkIdType v1) {
    std::vector<std::array<vtkIdType, 2>> edges;
    std::vector<vtkIdType> ends;
    long bad = 0, boundary = 0, nonManifold = 0;
    for (vtkIdType v = v0; v < v1; ++v) {
      const size_t b = static_cast<size_t>(start[static_cast<size_t>(v)]), e = static_cast<size_t>(start[static_cast<size_t>(v) + 1]);
      if (b == e) continue;
      edges.assign(link.begin() + static_cast<long>(b), link.begin() + static_cast<long>(e));
      if (triangles) {
        // Each edge (v, w) once, from its smaller end.
        ends.clear();
        for (const auto& edge : edges)
          for (vtkIdType w : edge)
            if (w > v) ends.push_back(w);
        std::sort(ends.begin(), ends.end());
        CountEdgeUses(ends, boundary, nonManifold);
      }
      // Walk the cycle from the first edge: a single fan visits every edge.
      size_t visited = 1;
      vtkIdType first = edges[0][0], at = edges[0][1];
      edges[0] = {-1, -1};
      bool closed = false;
      while (!closed) {
        bool found = false;
        for (auto& edge : edges) {
          if (edge[0] != at) continue;  // oriented fans: next edge starts where this one ends
          at = edge[1];
          edge = {-1, -1};
          ++visited;
          found = true;
          break;
        }
        if (!found || at == first) closed = true;
      }
      if (at != first || visited != edges.size()) ++bad;
    }
    badVertices += bad, boundaryEdges += boundary, nonManifoldEdges += nonManifold;
  });
  MeshTopology topology;
  topology.NonManifoldVertices = badVertices;
  if (triangles) {
    topology.BoundaryEdges = boundaryEdges, topology.NonManifoldEdges = nonManifoldEdges;
  } else {
    CountBadEdges(mesh, topology.BoundaryEdges, topology.NonManifoldEdges);
  }
  return topology;
}

void MeshVolumeAndArea(vtkPolyData* mesh, double& volume, double& area) {
  volume = area = 0;
  vtkPoints* points = mesh->GetPoints();
  vtkCellArray* polys = mesh->GetPolys();
  if (!points || !polys || polys->GetNumberOfCells() == 0) return;
  // Triangle fans of every polygon, summed in parallel (meshes have millions of triangles).
  const PointsView view(points);
  // Ids read in place when the storage is vtkIdType-sized (then thread-safe), else copied.
  const bool shared = polys->IsStorageShareable();
  vtkSMPThreadLocal<std::array<double, 2>> sums(std::array<double, 2>{0.0, 0.0});
  vtkSMPTools::For(0, polys->GetNumberOfCells(), [&](vtkIdType c0, vtkIdType c1) {
    auto& local = sums.Local();
    vtkNew<vtkIdList> copy;
    double a[3], b[3], c[3];
    for (vtkIdType cellId = c0; cellId < c1; ++cellId) {
      vtkIdType n;
      const vtkIdType* ids;
      if (shared) {
        polys->GetCellAtId(cellId, n, ids);
      } else {
        polys->GetCellAtId(cellId, copy);
        n = copy->GetNumberOfIds(), ids = copy->GetPointer(0);
      }
      if (n < 3) continue;
      view.Get(ids[0], a);
      for (vtkIdType t = 1; t + 1 < n; ++t) {
        view.Get(ids[t], b), view.Get(ids[t + 1], c);
        local[0] += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
        double f[3];
        TriangleCross(a, b, c, f);
        local[1] += 0.5 * std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      }
    }
  });
  for (const auto& local : sums) volume += local[0], area += local[1];
}

bool LabelmapToMesh(vtkImageData* labelmap, const vtkMatrix4x4* ijkToRAS, int label, const MeshOptions& options,
                    vtkPolyData* output, MeshStats& stats, std::string& error, const ProgressCallback& progress) {
  const auto t0 = Clock::now();
  stats = MeshStats();
  stats.Label = label;
  output->Initialize();
  if (!labelmap || !labelmap->GetPointData()->GetScalars() || labelmap->GetNumberOfPoints() == 0) {
    error = "the segmentation has no labelmap";
    return false;
  }
  if (!IntegerScalars(labelmap) || labelmap->GetNumberOfScalarComponents() != 1) {
    error = "the labelmap must hold one integer label per voxel";
    return false;
  }
  if (!ijkToRAS || std::abs(Determinant3(ijkToRAS)) < 1e-12) {
    error = "the labelmap's IJK-to-RAS matrix is missing or singular";
    return false;
  }
  if (options.Sigma < 0 || options.GridStep[0] <= 0 || options.GridStep[1] <= 0 || options.GridStep[2] <= 0 ||
      options.DecimationFraction < 0 || options.DecimationFraction >= 1) {
    error = "invalid mesh options (sigma >= 0, grid step > 0, decimation in [0, 1))";
    return false;
  }
  int dims[3];
  labelmap->GetDimensions(dims);
  const LabelBounds b = CachedBounds(labelmap, dims, label);
  stats.LabelVoxels = b.Count;
  const double voxelVolume = std::abs(Determinant3(ijkToRAS));
  stats.LabelVolumeMm3 = static_cast<double>(b.Count) * voxelVolume;
  if (b.Empty()) {
    error = "segment with label " + std::to_string(label) + " is empty (no voxels)";
    return false;
  }
  for (int a = 0; a < 3; ++a) stats.TouchesBorder = stats.TouchesBorder || b.Lo[a] == 0 || b.Hi[a] == dims[a] - 1;
  if (stats.TouchesBorder) stats.Warnings.push_back("segment touches the volume border: closed by padding (flat cap)");

  bool ok = false;
  stats.Method = MeshMethodName(options.Method);
  if (options.Method == MeshMethod::Gaussian) {
    ok = GaussianMesh(labelmap, ijkToRAS, label, b, options, output, stats, error, progress);
    double volume = 0, area = 0;
    if (ok) MeshVolumeAndArea(output, volume, area);
    if (!ok || volume < 0.5 * stats.LabelVolumeMm3) {
      // Should not happen with the voxel-centre constraint; kept as a safety net.
      stats.Warnings.push_back("gaussian surface failed (" + (ok ? "lost half the volume" : error) +
                               "): used the discrete surface");
      MeshOptions fallback = options;
      fallback.Method = MeshMethod::Discrete;
      stats.Method = "discrete (gaussian failed)";
      error.clear();
      ok = DiscreteMesh(labelmap, ijkToRAS, label, b, fallback, output, stats, error, progress);
    }
  } else {
    ok = DiscreteMesh(labelmap, ijkToRAS, label, b, options, output, stats, error, progress);
  }
  if (!ok) {
    output->Initialize();
    return false;
  }
  if (options.DecimationFraction > 0) {
    if (progress) progress(0.8, "decimating");
    Decimate(output, options.DecimationFraction, stats);
  }
  if (options.CorrectVolume && options.Method != MeshMethod::SlicerDefault) {
    double volume = 0, area = 0;
    MeshVolumeAndArea(output, volume, area);
    const double mismatch = std::abs(volume - stats.LabelVolumeMm3) / stats.LabelVolumeMm3;
    // The offset that would fix the volume. More than half a voxel means the mesh lacks whole
    // structures below the smoothing scale (noise specks, pinholes): a global offset would
    // distort the rest, so the mismatch is reported instead.
    double minSpacing = 1e300;
    for (int a = 0; a < 3; ++a) {
      double len = 0;
      for (int r = 0; r < 3; ++r) len += ijkToRAS->GetElement(r, a) * ijkToRAS->GetElement(r, a);
      minSpacing = std::min(minSpacing, std::sqrt(len));
    }
    const double offset = area > 0 ? std::abs(stats.LabelVolumeMm3 - volume) / area : 0.0;
    if (offset > 0.5 * minSpacing && stats.LabelVoxels > 64) {
      stats.Warnings.push_back("mesh volume differs from the labelmap by " +
                               std::to_string(static_cast<int>(std::round(100 * mismatch))) +
                               " % (noise or structures below the smoothing scale): volume not corrected; "
                               "clean the segment first (keep largest, fill holes, opening)");
    } else {
      if (progress) progress(0.9, "volume correction");
      stats.VolumeCorrectionMm = CorrectVolume(output, stats.LabelVolumeMm3);
    }
  }
  FillStats(output, stats);
  if (!stats.Watertight) {
    stats.Warnings.push_back("mesh is not watertight: " + std::to_string(stats.BoundaryEdges) + " boundary and " +
                             std::to_string(stats.NonManifoldEdges) + " non-manifold edges");
  } else if (!stats.Manifold) {
    stats.Warnings.push_back("mesh has " + std::to_string(stats.NonManifoldVertices) + " non-manifold vertices");
  }
  stats.Seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (progress) progress(1.0, "done");
  return true;
}

void ComputeMeshNormals(vtkPolyData* mesh) { ComputeVertexNormals(mesh); }
double CorrectMeshVolume(vtkPolyData* mesh, double targetVolume) { return CorrectVolume(mesh, targetVolume); }
void FillMeshStats(vtkPolyData* mesh, MeshStats& stats) { FillStats(mesh, stats); }

}  // namespace rp
