#include "rpDrillBoneBuilder.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <memory>
#include <cmath>
#include <limits>

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkType.h>

#include "rpBlockMesher.h"
#include "rpDrillDisplay.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpLabelmapToMesh.h"
#include "rpMeshSignedDistance.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

bool FindDrillSegments(vtkRPSegmentationNode* segmentation, const std::vector<std::string>& refs, DrillSegments& found,
                       std::string& error) {
  for (const std::string& ref : refs) {
    const vtkRPSegmentationNode::Segment* segment = segmentation->GetSegmentByID(ref);
    for (int n = 0; !segment && n < segmentation->GetNumberOfSegments(); ++n) {
      const auto& s = segmentation->GetNthSegment(n);
      if (s.Name.size() == ref.size() && std::equal(ref.begin(), ref.end(), s.Name.begin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
          }))
        segment = &s;
    }
    if (!segment && !ref.empty() && ref.find_first_not_of("0123456789") == std::string::npos)
      segment = segmentation->GetSegmentByLabel(std::stoi(ref));
    if (!segment) {
      error = "no segment '" + ref + "' in the segmentation (segments:";
      for (int n = 0; n < segmentation->GetNumberOfSegments(); ++n) error += " " + segmentation->GetNthSegment(n).ID;
      error += ")";
      return false;
    }
    found.Labels.push_back(segment->LabelValue);
    found.Tissues.push_back(segment->TissueClass);
    found.IDs.push_back(segment->ID);
    found.Names.push_back(segment->Name.empty() ? segment->ID : segment->Name);
  }
  return true;
}

namespace {

constexpr uint8_t ProtectedCode = 0x80;
constexpr uint8_t BoneMask = 0x3f;  // 1 + index of the bone label

// A box of a volume copied out as codes or values (index (i,j,k) in the source's IJK).
template <typename T>
struct Crop {
  int Lo[3] = {0, 0, 0}, Dims[3] = {0, 0, 0};
  std::vector<T> Values;
  T At(int i, int j, int k) const {
    i -= this->Lo[0], j -= this->Lo[1], k -= this->Lo[2];
    if (i < 0 || j < 0 || k < 0 || i >= this->Dims[0] || j >= this->Dims[1] || k >= this->Dims[2]) return T{};
    return this->Values[(size_t(k) * this->Dims[1] + j) * this->Dims[0] + i];
  }
  T Clamped(int i, int j, int k) const {
    i = std::clamp(i - this->Lo[0], 0, this->Dims[0] - 1);
    j = std::clamp(j - this->Lo[1], 0, this->Dims[1] - 1);
    k = std::clamp(k - this->Lo[2], 0, this->Dims[2] - 1);
    return this->Values[(size_t(k) * this->Dims[1] + j) * this->Dims[0] + i];
  }
};

// Codes of every voxel: bone label index + 1, | ProtectedCode.
template <typename T>
void ScanLabels(const T* labels, const int dims[3], const std::vector<int>& bone, const std::vector<int>& protectedLabels,
                int boneBox[6], int protectedBox[6], Crop<uint8_t>* crop) {
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j) {
      const T* row = labels + (size_t(k) * dims[1] + j) * dims[0];
      for (int i = 0; i < dims[0]; ++i) {
        const long long value = static_cast<long long>(row[i]);
        if (value == 0) continue;
        uint8_t code = 0;
        for (size_t b = 0; b < bone.size(); ++b)
          if (value == bone[b]) code = static_cast<uint8_t>(b + 1);
        for (int p : protectedLabels)
          if (value == p) code |= ProtectedCode;
        if (code == 0) continue;
        const int ijk[3] = {i, j, k};
        for (int* box : {(code & BoneMask) ? boneBox : nullptr, (code & ProtectedCode) ? protectedBox : nullptr}) {
          if (box == nullptr) continue;
          for (int a = 0; a < 3; ++a) box[2 * a] = std::min(box[2 * a], ijk[a]), box[2 * a + 1] = std::max(box[2 * a + 1], ijk[a]);
        }
        if (crop) {
          const int ci = i - crop->Lo[0], cj = j - crop->Lo[1], ck = k - crop->Lo[2];
          if (ci >= 0 && cj >= 0 && ck >= 0 && ci < crop->Dims[0] && cj < crop->Dims[1] && ck < crop->Dims[2])
            crop->Values[(size_t(ck) * crop->Dims[1] + cj) * crop->Dims[0] + ci] = code;
        }
      }
    }
}

template <typename T>
void CopyValues(const T* values, const int dims[3], Crop<float>& crop) {
  for (int k = 0; k < crop.Dims[2]; ++k)
    for (int j = 0; j < crop.Dims[1]; ++j)
      for (int i = 0; i < crop.Dims[0]; ++i)
        crop.Values[(size_t(k) * crop.Dims[1] + j) * crop.Dims[0] + i] =
            static_cast<float>(values[(size_t(k + crop.Lo[2]) * dims[1] + (j + crop.Lo[1])) * dims[0] + (i + crop.Lo[0])]);
}

struct Affine {
  double M[3][4];
  explicit Affine(const vtkMatrix4x4* m) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) this->M[r][c] = m->GetElement(r, c);
  }
  Vec3 Apply(const Vec3& p) const {
    return {M[0][0] * p.x + M[0][1] * p.y + M[0][2] * p.z + M[0][3], M[1][0] * p.x + M[1][1] * p.y + M[1][2] * p.z + M[1][3],
            M[2][0] * p.x + M[2][1] * p.y + M[2][2] * p.z + M[2][3]};
  }
  // Gradient in RAS from a gradient in IJK (the chain rule through RAS → IJK).
  Vec3 PullBack(const Vec3& g) const {
    return {M[0][0] * g.x + M[1][0] * g.y + M[2][0] * g.z, M[0][1] * g.x + M[1][1] * g.y + M[2][1] * g.z,
            M[0][2] * g.x + M[1][2] * g.y + M[2][2] * g.z};
  }
};

// Trilinear value and IJK gradient of an indicator at a continuous index.
template <typename Pred>
void Trilinear(const Crop<uint8_t>& crop, const Vec3& x, Pred inside, double& value, Vec3& gradient) {
  const int i = static_cast<int>(std::floor(x.x)), j = static_cast<int>(std::floor(x.y)), k = static_cast<int>(std::floor(x.z));
  const double u = x.x - i, v = x.y - j, w = x.z - k;
  double c[2][2][2];
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) c[dk][dj][di] = inside(crop.At(i + di, j + dj, k + dk)) ? 1.0 : 0.0;
  const double c00 = c[0][0][0] * (1 - u) + c[0][0][1] * u, c01 = c[0][1][0] * (1 - u) + c[0][1][1] * u;
  const double c10 = c[1][0][0] * (1 - u) + c[1][0][1] * u, c11 = c[1][1][0] * (1 - u) + c[1][1][1] * u;
  const double c0 = c00 * (1 - v) + c01 * v, c1 = c10 * (1 - v) + c11 * v;
  value = c0 * (1 - w) + c1 * w;
  const double dx0 = (c[0][0][1] - c[0][0][0]) * (1 - v) + (c[0][1][1] - c[0][1][0]) * v;
  const double dx1 = (c[1][0][1] - c[1][0][0]) * (1 - v) + (c[1][1][1] - c[1][1][0]) * v;
  gradient = {dx0 * (1 - w) + dx1 * w, (c01 - c00) * (1 - w) + (c11 - c10) * w, c1 - c0};
}

// Signed distance (mm, > 0 outside) to the ½ iso-surface of an interpolated indicator, to first order.
double IndicatorDistance(double value, const Vec3& gradientRAS) {
  const double g = Norm(gradientRAS);
  if (g < 1e-9) return value >= 0.5 ? -1e9 : 1e9;
  return (0.5 - value) / g;
}

// Whether a drill block lies near a labelmap voxel with any of the `mask` bits (cheap skip test).
bool BlockNearCodes(const Crop<uint8_t>& crop, const Affine& rasToIJK, const DrillGrid& grid, int bi, int bj, int bk,
                    uint8_t mask) {
  const int E = DrillVolume::BlockEdge;
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 ijk = rasToIJK.Apply(grid.Center(bi * E + ((corner & 1) ? E : -1), bj * E + ((corner & 2) ? E : -1),
                                                bk * E + ((corner & 4) ? E : -1)));
    lo = Min(lo, ijk);
    hi = Max(hi, ijk);
  }
  for (int k = int(std::floor(lo.z)) - 1; k <= int(std::ceil(hi.z)) + 1; ++k)
    for (int j = int(std::floor(lo.y)) - 1; j <= int(std::ceil(hi.y)) + 1; ++j)
      for (int i = int(std::floor(lo.x)) - 1; i <= int(std::ceil(hi.x)) + 1; ++i)
        if (crop.At(i, j, k) & mask) return true;
  return false;
}

// The protected structures' ½ surface on their own grid (the whole structure, not only what
// lies in the drill region: the distance read-out needs it all), at the drill voxel size or half
// the labelmap's, whichever is coarser.
bool BuildProtectedSurface(const Crop<uint8_t>& crop, const int box[6], const Affine& ijkToRAS, const Affine& rasToIJK,
                           const ImageVolume& labels, double spacing, const std::vector<Material>& materials,
                           DrillVolume& surface, std::string& error) {
  double labelSpacing[3];
  labels.GetSpacing(labelSpacing);
  const double h = std::max(spacing, 0.5 * std::min({labelSpacing[0], labelSpacing[1], labelSpacing[2]}));
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 ras = ijkToRAS.Apply({double((corner & 1) ? box[1] + 1 : box[0] - 1), double((corner & 2) ? box[3] + 1 : box[2] - 1),
                                     double((corner & 4) ? box[5] + 1 : box[4] - 1)});
    lo = Min(lo, ras);
    hi = Max(hi, ras);
  }
  DrillGrid grid;
  grid.Spacing = h;
  grid.Origin = lo - Vec3{2 * h, 2 * h, 2 * h};
  for (int a = 0; a < 3; ++a) grid.Dimensions[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / h)) + 5;
  if (!surface.Initialize(grid, materials, error)) return false;
  const int E = DrillVolume::BlockEdge;
  const auto& blocks = surface.BlockDimensions();
  for (int bk = 0; bk < blocks[2]; ++bk)
    for (int bj = 0; bj < blocks[1]; ++bj)
      for (int bi = 0; bi < blocks[0]; ++bi) {
        if (!BlockNearCodes(crop, rasToIJK, grid, bi, bj, bk, ProtectedCode)) continue;
        for (int k = bk * E; k < std::min(bk * E + E, grid.Dimensions[2]); ++k)
          for (int j = bj * E; j < std::min(bj * E + E, grid.Dimensions[1]); ++j)
            for (int i = bi * E; i < std::min(bi * E + E, grid.Dimensions[0]); ++i) {
              double f;
              Vec3 g;
              Trilinear(crop, rasToIJK.Apply(grid.Center(i, j, k)), [](uint8_t c) { return (c & ProtectedCode) != 0; }, f, g);
              if (f <= 0) continue;
              const double rho = DrillVolume::RampDensity(IndicatorDistance(f, rasToIJK.PullBack(g)), h);
              if (rho > 0) surface.SetVoxel(i, j, k, DrillVolume::Quantize(rho), 1, false);
            }
      }
  surface.Finish();
  return true;
}

// The bone labels around the drill grid (six labelmap voxels more, so the caps where this box
// cuts the bone stay off the grid) meshed as the segment models are: Gaussian, σ = 1 voxel.
bool MeshBoneLabels(const Crop<uint8_t>& crop, const vtkMatrix4x4* ijkToRAS, const Affine& rasToIJK, const DrillGrid& grid,
                    TriangleMesh& mesh, std::string& error) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 ijk = rasToIJK.Apply(grid.Center((corner & 1) ? grid.Dimensions[0] : -1, (corner & 2) ? grid.Dimensions[1] : -1,
                                                (corner & 4) ? grid.Dimensions[2] : -1));
    lo = Min(lo, ijk);
    hi = Max(hi, ijk);
  }
  int box[3], dims[3];
  for (int a = 0; a < 3; ++a) {
    box[a] = std::clamp(static_cast<int>(std::floor(lo[a])) - 6, crop.Lo[a], crop.Lo[a] + crop.Dims[a] - 1);
    const int last = std::clamp(static_cast<int>(std::ceil(hi[a])) + 6, crop.Lo[a], crop.Lo[a] + crop.Dims[a] - 1);
    dims[a] = last - box[a] + 1;
  }
  vtkNew<vtkImageData> mask;
  mask->SetDimensions(dims);
  mask->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* out = static_cast<unsigned char*>(mask->GetScalarPointer());
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        *out++ = (crop.At(box[0] + i, box[1] + j, box[2] + k) & BoneMask) ? 1 : 0;
  vtkNew<vtkMatrix4x4> toRAS;
  toRAS->DeepCopy(ijkToRAS);
  for (int r = 0; r < 3; ++r)
    toRAS->SetElement(r, 3, ijkToRAS->GetElement(r, 0) * box[0] + ijkToRAS->GetElement(r, 1) * box[1] +
                                ijkToRAS->GetElement(r, 2) * box[2] + ijkToRAS->GetElement(r, 3));
  vtkNew<vtkPolyData> poly;
  MeshStats stats;
  if (!LabelmapToMesh(mask, toRAS, 1, MeshOptions{}, poly, stats, error)) return false;
  return PolyDataToTriangleMesh(poly, nullptr, mesh, error);
}

// Densities of the 8³ voxels of block (bi, bj, bk) from the signed distance to the surface, a 4³
// sub-block at a time: a sub-block whose centre is farther than its half-diagonal plus a voxel
// from the surface is all bone or all air (|sd(p) − sd(c)| <= |p − c|), and so is any voxel the
// same bound decides; the others get one query each.
void SurfaceDensities(const MeshSignedDistance& surface, const DrillGrid& grid, int bi, int bj, int bk, uint8_t out[]) {
  const double h = grid.Spacing;
  const double reach = 1.5 * std::sqrt(3.0) * h + h;
  const int E = DrillVolume::BlockEdge;
  for (int sub = 0; sub < 8; ++sub) {
    const int i0 = bi * E + (sub & 1) * 4, j0 = bj * E + ((sub >> 1) & 1) * 4, k0 = bk * E + (sub >> 2) * 4;
    const Vec3 c = grid.Origin + Vec3{i0 + 1.5, j0 + 1.5, k0 + 1.5} * h;
    const double sc = surface.SignedDistance(c);
    for (int k = k0; k < k0 + 4; ++k)
      for (int j = j0; j < j0 + 4; ++j)
        for (int i = i0; i < i0 + 4; ++i) {
          uint8_t& q = out[DrillVolume::Local(i, j, k)];
          const Vec3 p = grid.Center(i, j, k);
          const double away = sc > reach || sc < -reach ? 0.0 : Norm(p - c);
          if (sc - away >= h) q = 0;
          else if (sc + away <= -h) q = 255;
          else q = DrillVolume::Quantize(DrillVolume::RampDensity(surface.SignedDistance(p), h));
        }
  }
}

// Whether block (bi, bj, bk) has a voxel within the ramp of the surface or inside it.
bool BlockNearSurface(const MeshSignedDistance& surface, const DrillGrid& grid, int bi, int bj, int bk) {
  const double h = grid.Spacing;
  const int E = DrillVolume::BlockEdge;
  const Vec3 c = grid.Origin + Vec3{bi * E + 3.5, bj * E + 3.5, bk * E + 3.5} * h;
  const double reach = 3.5 * std::sqrt(3.0) * h + h;
  const Vec3 slack{reach, reach, reach};
  const Vec3 lo = surface.Lo() - slack, hi = surface.Hi() + slack;
  if (c.x < lo.x || c.y < lo.y || c.z < lo.z || c.x > hi.x || c.y > hi.y || c.z > hi.z) return false;
  return surface.SignedDistance(c) < reach;
}

// The CT's values around the drill grid (for the HU rule), and its RAS → IJK; false without a CT.
bool CropCT(const ImageVolume& source, const DrillGrid& grid, Crop<float>& ct, std::unique_ptr<Affine>& rasToCT) {
  const double h = grid.Spacing;
  if (!(source.Image && source.Image->GetNumberOfPoints() > 0 && source.Image->GetPointData()->GetScalars())) return false;
  vtkNew<vtkMatrix4x4> inverse;
  vtkMatrix4x4::Invert(source.IJKToRAS, inverse);
  rasToCT = std::make_unique<Affine>(inverse);
  int ctDims[3];
  source.Image->GetDimensions(ctDims);
  Vec3 clo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 ras = grid.Origin + Vec3{(corner & 1) ? grid.Dimensions[0] * h : 0.0, (corner & 2) ? grid.Dimensions[1] * h : 0.0,
                                        (corner & 4) ? grid.Dimensions[2] * h : 0.0};
    const Vec3 ijk = rasToCT->Apply(ras);
    clo = Min(clo, ijk);
    chi = Max(chi, ijk);
  }
  for (int a = 0; a < 3; ++a) {
    ct.Lo[a] = std::clamp(static_cast<int>(std::floor(clo[a])) - 1, 0, ctDims[a] - 1);
    ct.Dims[a] = std::clamp(static_cast<int>(std::ceil(chi[a])) + 1, 0, ctDims[a] - 1) - ct.Lo[a] + 1;
  }
  ct.Values.assign(size_t(ct.Dims[0]) * ct.Dims[1] * ct.Dims[2], 0.0f);
  switch (source.Image->GetScalarType()) {
    vtkTemplateMacro(CopyValues(static_cast<const VTK_TT*>(source.Image->GetScalarPointer()), ctDims, ct));
  }
  return true;
}

// The material of a bone voxel by its HU (the brightest of the 8 CT voxels around it in the
// surface ramp, where partial volume with soft tissue thins the cortex); huRule highest first.
uint8_t MaterialByHU(const Crop<float>& ct, const Affine& rasToCT, const Vec3& ras, bool inRamp,
                     const std::vector<std::pair<double, uint8_t>>& huRule) {
  const Vec3 c = rasToCT.Apply(ras);
  const int ci = int(std::floor(c.x)), cj = int(std::floor(c.y)), ck = int(std::floor(c.z));
  const double u = c.x - ci, v = c.y - cj, w = c.z - ck;
  double hu = 0, brightest = -std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
    const double value = ct.Clamped(ci + di, cj + dj, ck + dk);
    hu += value * (di ? u : 1 - u) * (dj ? v : 1 - v) * (dk ? w : 1 - w);
    brightest = std::max(brightest, value);
  }
  if (inRamp) hu = brightest;
  for (const auto& [threshold, m] : huRule)
    if (hu >= threshold) return m;
  return huRule.back().second;
}

// The smooth surface the density follows: the given mesh, or the bone labels meshed here.
bool SmoothSurfaceFor(const DrillBoneSource& source, const Crop<uint8_t>& crop, const Affine& rasToIJK,
                      const DrillGrid& grid, MeshSignedDistance& surface, DrillBoneReport& report, std::string& error) {
  TriangleMesh mesh = source.BoneSurface;
  report.Surface = mesh.Triangles.empty() ? "labels meshed here (Gaussian, sigma 1 voxel)" : "given mesh";
  if (mesh.Triangles.empty() && !MeshBoneLabels(crop, source.Labels.IJKToRAS, rasToIJK, grid, mesh, error)) {
    error = "drill bone: meshing the bone labels: " + error;
    return false;
  }
  if (!surface.Build(mesh, error)) {
    error = "drill bone: the bone surface: " + error;
    return false;
  }
  report.SurfaceTriangles = mesh.Triangles.size();
  return true;
}

bool CheckSolidInputs(const DrillBoneSource& source, const std::vector<Material>& materials, std::string& error) {
  if (!(source.Spacing >= 0.05 && source.Spacing <= 5.0)) {
    error = "drill bone: the voxel size must be between 0.05 and 5 mm";
    return false;
  }
  if (materials.empty()) {
    error = "drill bone: the material table has no drillable material (a \"hardness\")";
    return false;
  }
  if (source.BoneLabels.size() > BoneMask) {
    error = "drill bone: at most 63 bone segments";
    return false;
  }
  return true;
}

// Steps 1 and 2: where the bone and the protected structures are, and the labelmap box to
// copy (bone and protected voxels, two voxels around) as codes.
bool CropBoneLabels(const DrillBoneSource& source, Crop<uint8_t>& crop, int boneBox[6], int protectedBox[6],
                    DrillBoneReport& report, std::string& error) {
  vtkImageData* labels = source.Labels.Image;
  int dims[3];
  labels->GetDimensions(dims);
  for (int a = 0; a < 6; ++a) boneBox[a] = protectedBox[a] = (a % 2 == 0) ? INT32_MAX : INT32_MIN;
  switch (labels->GetScalarType()) {
    vtkTemplateMacro(ScanLabels(static_cast<const VTK_TT*>(labels->GetScalarPointer()), dims, source.BoneLabels,
                                source.ProtectedLabels, boneBox, protectedBox, nullptr));
  }
  if (boneBox[0] > boneBox[1]) {
    error = "drill bone: no voxel of the bone segment (label";
    for (int l : source.BoneLabels) error += " " + std::to_string(l);
    error += ") in the labelmap";
    return false;
  }
  report.HasProtected = protectedBox[0] <= protectedBox[1];
  for (int a = 0; a < 3; ++a) {
    int lo = boneBox[2 * a], hi = boneBox[2 * a + 1];
    if (report.HasProtected) lo = std::min(lo, protectedBox[2 * a]), hi = std::max(hi, protectedBox[2 * a + 1]);
    crop.Lo[a] = std::max(0, lo - 2);
    crop.Dims[a] = std::min(dims[a] - 1, hi + 2) - crop.Lo[a] + 1;
  }
  crop.Values.assign(size_t(crop.Dims[0]) * crop.Dims[1] * crop.Dims[2], 0);
  switch (labels->GetScalarType()) {
    vtkTemplateMacro(ScanLabels(static_cast<const VTK_TT*>(labels->GetScalarPointer()), dims, source.BoneLabels,
                                source.ProtectedLabels, boneBox, protectedBox, &crop));
  }
  return true;
}

// Step 3: the drill grid, the RAS box of the copied labels (or the region) plus a margin.
bool DrillGridAround(const DrillBoneSource& source, const Crop<uint8_t>& crop, const Affine& ijkToRAS, DrillGrid& grid,
                     std::string& error) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 ijk{double(crop.Lo[0] + ((corner & 1) ? crop.Dims[0] - 1 : 0)),
                   double(crop.Lo[1] + ((corner & 2) ? crop.Dims[1] - 1 : 0)),
                   double(crop.Lo[2] + ((corner & 4) ? crop.Dims[2] - 1 : 0))};
    const Vec3 ras = ijkToRAS.Apply(ijk);
    lo = Min(lo, ras);
    hi = Max(hi, ras);
  }
  if (source.HasRegion) {
    lo = Max(lo, source.RegionLo);
    hi = Min(hi, source.RegionHi);
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
      error = "drill bone: the region does not overlap the bone";
      return false;
    }
  }
  const double h = source.Spacing;
  grid.Spacing = h;
  grid.Origin = lo - Vec3{3 * h, 3 * h, 3 * h};
  for (int a = 0; a < 3; ++a) grid.Dimensions[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / h)) + 7;
  return true;
}

// The HU rule: drillable materials with a ctMinHU, highest threshold first.
std::vector<std::pair<double, uint8_t>> HURule(const std::vector<Material>& materials) {
  std::vector<std::pair<double, uint8_t>> huRule;
  for (size_t m = 0; m < materials.size(); ++m)
    if (std::isfinite(materials[m].CTMinHU)) huRule.push_back({materials[m].CTMinHU, static_cast<uint8_t>(m + 1)});
  std::sort(huRule.rbegin(), huRule.rend());
  return huRule;
}

// Material of each bone label (index 1 + bone) without a CT: its tissue class when drillable.
std::vector<uint8_t> LabelMaterials(const DrillBoneSource& source, const std::vector<Material>& materials) {
  std::vector<uint8_t> labelMaterial(source.BoneLabels.size() + 1, 1);
  for (size_t b = 0; b < source.BoneLabels.size(); ++b) {
    const std::string tissue = b < source.BoneTissues.size() ? source.BoneTissues[b] : "";
    for (size_t m = 0; m < materials.size(); ++m)
      if (!tissue.empty() && materials[m].Tissue.size() == tissue.size() &&
          std::equal(tissue.begin(), tissue.end(), materials[m].Tissue.begin(),
                     [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); }))
        labelMaterial[b + 1] = static_cast<uint8_t>(m + 1);
  }
  return labelMaterial;
}

// What step 4 reads to fill the drill voxels.
struct SolidSources {
  const Crop<uint8_t>& Labels;
  const Affine& RASToIJK;
  const DrillGrid& Grid;
  const MeshSignedDistance& Surface;  // empty: the label mask's density
  const Crop<float>& CT;
  const Affine* RASToCT;  // null: materials by bone label
  const std::vector<std::pair<double, uint8_t>>& HURule;
  const std::vector<uint8_t>& LabelMaterial;
};

// The material of a voxel with bone density: by the CT's HU, else by the bone label of the
// nearest labelmap voxel (or any bone corner around).
uint8_t MaterialAt(const SolidSources& in, const Vec3& ras, const Vec3& x, uint8_t q) {
  if (in.RASToCT) return MaterialByHU(in.CT, *in.RASToCT, ras, q < 255, in.HURule);
  const Crop<uint8_t>& crop = in.Labels;
  uint8_t code = crop.At(int(std::lround(x.x)), int(std::lround(x.y)), int(std::lround(x.z))) & BoneMask;
  for (int corner = 0; corner < 8 && code == 0; ++corner)
    code = crop.At(int(std::floor(x.x)) + (corner & 1), int(std::floor(x.y)) + ((corner >> 1) & 1),
                   int(std::floor(x.z)) + (corner >> 2)) & BoneMask;
  return in.LabelMaterial[code ? code : 1];  // inside the smooth surface, off the labels
}

// The voxels of one block: density, material and protection.
void FillBlock(const SolidSources& in, int bi, int bj, int bk, const uint8_t* surfaceQ, DrillVolume& bone) {
  const int E = DrillVolume::BlockEdge;
  const DrillGrid& grid = in.Grid;
  const bool smooth = !in.Surface.Empty();
  for (int k = bk * E; k < std::min(bk * E + E, grid.Dimensions[2]); ++k)
    for (int j = bj * E; j < std::min(bj * E + E, grid.Dimensions[1]); ++j)
      for (int i = bi * E; i < std::min(bi * E + E, grid.Dimensions[0]); ++i) {
        const Vec3 ras = grid.Center(i, j, k);
        const Vec3 x = in.RASToIJK.Apply(ras);
        double f, fp;
        Vec3 g, gp;
        Trilinear(in.Labels, x, [](uint8_t c) { return (c & BoneMask) != 0; }, f, g);
        Trilinear(in.Labels, x, [](uint8_t c) { return (c & ProtectedCode) != 0; }, fp, gp);
        const bool isProtected = fp >= 0.5;
        const uint8_t q = smooth ? surfaceQ[DrillVolume::Local(i, j, k)]
                                 : DrillVolume::Quantize(DrillVolume::RampDensity(IndicatorDistance(f, in.RASToIJK.PullBack(g)), grid.Spacing));
        if (q == 0 && !isProtected) continue;
        const uint8_t material = q > 0 ? MaterialAt(in, ras, x, q) : 0;
        bone.SetVoxel(i, j, k, q, material, isProtected);
      }
}

// Step 4: voxels, block by block; blocks with no bone or protected label near them are skipped.
void FillSolid(const SolidSources& in, DrillVolume& bone, const ProgressCallback& progress) {
  const bool smooth = !in.Surface.Empty();
  const DrillGrid& grid = in.Grid;
  uint8_t surfaceQ[DrillVolume::BlockVoxels];
  const auto& blockDims = bone.BlockDimensions();
  const size_t blockCount = size_t(blockDims[0]) * blockDims[1] * blockDims[2];
  size_t visited = 0;
  for (int bk = 0; bk < blockDims[2]; ++bk) {
    for (int bj = 0; bj < blockDims[1]; ++bj)
      for (int bi = 0; bi < blockDims[0]; ++bi, ++visited) {
        const bool nearBone = smooth ? BlockNearSurface(in.Surface, grid, bi, bj, bk)
                                     : BlockNearCodes(in.Labels, in.RASToIJK, grid, bi, bj, bk, BoneMask);
        if (!nearBone && !BlockNearCodes(in.Labels, in.RASToIJK, grid, bi, bj, bk, ProtectedCode)) continue;
        if (smooth) {
          if (nearBone) SurfaceDensities(in.Surface, grid, bi, bj, bk, surfaceQ);
          else std::fill(surfaceQ, surfaceQ + DrillVolume::BlockVoxels, uint8_t(0));
        }
        FillBlock(in, bi, bj, bk, surfaceQ, bone);
      }
    if (progress) progress(0.05 + 0.9 * double(visited) / double(blockCount), "voxels");
  }
}

bool BuildSolid(const DrillBoneSource& source, const std::vector<Material>& materials, DrillVolume& bone,
                DrillVolume* protectedSurface, DrillBoneReport& report, std::string& error,
                const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  report = DrillBoneReport{};
  if (!CheckSolidInputs(source, materials, error)) return false;
  Crop<uint8_t> crop;
  int boneBox[6], protectedBox[6];
  if (!CropBoneLabels(source, crop, boneBox, protectedBox, report, error)) return false;
  if (progress) progress(0.05, "labels read");
  const Affine ijkToRAS(source.Labels.IJKToRAS);
  vtkNew<vtkMatrix4x4> rasToIJKMatrix;
  vtkMatrix4x4::Invert(source.Labels.IJKToRAS, rasToIJKMatrix);
  const Affine rasToIJK(rasToIJKMatrix);
  DrillGrid grid;
  if (!DrillGridAround(source, crop, ijkToRAS, grid, error)) return false;
  if (!bone.Initialize(grid, materials, error)) return false;
  report.GridVoxels = grid.VoxelCount();

  // CT values around the grid, for the HU rule.
  Crop<float> ct;
  std::unique_ptr<Affine> rasToCT;
  report.UsedCT = CropCT(source.CT, grid, ct, rasToCT);
  const std::vector<std::pair<double, uint8_t>> huRule = HURule(materials);
  if (report.UsedCT && huRule.empty()) {
    error = "drill bone: a CT was given but no drillable material has a \"ctMinHU\"";
    return false;
  }
  const std::vector<uint8_t> labelMaterial = LabelMaterials(source, materials);

  // The smooth surface the density follows (or the label mask's).
  auto smooth = std::make_shared<MeshSignedDistance>();
  MeshSignedDistance& surface = *smooth;
  report.Surface = "label mask (trilinear)";
  if (source.SmoothSurface && !SmoothSurfaceFor(source, crop, rasToIJK, grid, surface, report, error)) return false;
  if (!surface.Empty()) report.BoneSurface = smooth;
  if (progress) progress(0.15, "bone surface");

  FillSolid({crop, rasToIJK, grid, surface, ct, rasToCT.get(), huRule, labelMaterial}, bone, progress);
  bone.Finish();
  if (protectedSurface && report.HasProtected &&
      !BuildProtectedSurface(crop, protectedBox, ijkToRAS, rasToIJK, source.Labels, source.Spacing, materials,
                             *protectedSurface, error))
    return false;
  report.StoredBlocks = bone.AllocatedBlocks();
  report.MemoryMB = bone.MemoryBytes() / 1e6;
  report.VolumeMm3 = bone.OriginalVolumes();
  report.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double total = 0;
  for (double v : report.VolumeMm3) total += v;
  if (total <= 0) {
    error = "drill bone: the bone segment has no volume on the drill grid (region outside the bone?)";
    return false;
  }
  if (progress) progress(1.0, "done");
  return true;
}

}  // namespace

bool BuildDrillBone(const DrillBoneSource& source, const std::vector<Material>& materials, DrillVolume& bone,
                    DrillVolume* protectedSurface, DrillBoneReport& report, std::string& error,
                    const ProgressCallback& progress) {
  vtkImageData* labels = source.Labels.Image;
  if (labels == nullptr || labels->GetNumberOfPoints() == 0 || labels->GetPointData()->GetScalars() == nullptr) {
    error = "drill bone: the segmentation has no labelmap";
    return false;
  }
  if (!vtkRPSegmentationNode::IsLabelScalarType(labels->GetScalarType()) || labels->GetNumberOfScalarComponents() != 1) {
    error = "drill bone: the labelmap must hold integer labels (one component)";
    return false;
  }
  if (source.BoneLabels.empty()) {
    error = "drill bone: no bone segment chosen";
    return false;
  }
  // Protected segments of a drillable tissue are solid bone too (felt, never removed).
  DrillBoneSource solid = source;
  for (size_t p = 0; p < source.ProtectedLabels.size(); ++p) {
    const std::string tissue = p < source.ProtectedTissues.size() ? source.ProtectedTissues[p] : "";
    bool drillable = false;
    for (const Material& m : materials)
      drillable = drillable || (!tissue.empty() && m.Tissue.size() == tissue.size() &&
                                std::equal(tissue.begin(), tissue.end(), m.Tissue.begin(), [](char a, char b) {
                                  return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
                                }));
    if (drillable && std::find(solid.BoneLabels.begin(), solid.BoneLabels.end(), source.ProtectedLabels[p]) == solid.BoneLabels.end()) {
      solid.BoneLabels.push_back(source.ProtectedLabels[p]);
      solid.BoneTissues.push_back(tissue);
    }
  }
  return BuildSolid(solid, materials, bone, protectedSurface, report, error, progress);
}

SurfaceFit MeasureSurfaceFit(DrillVolume& bone, const TriangleMesh& surface) {
  SurfaceFit fit;
  BVH tree;
  tree.Build(surface);
  if (tree.Empty()) return fit;
  const DrillGrid& grid = bone.Grid();
  const double border = 2 * grid.Spacing;
  const Vec3 lo = grid.Origin + Vec3{border, border, border};
  const Vec3 hi = grid.Center(grid.Dimensions[0] - 1, grid.Dimensions[1] - 1, grid.Dimensions[2] - 1) - Vec3{border, border, border};
  std::vector<double> distances;
  for (const Vec3& p : ContourToTriangleMesh(bone).Points) {
    if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z) continue;
    ClosestPointHit hit;
    if (!tree.ClosestPoint(p, HUGE_VAL, hit)) continue;
    distances.push_back(std::sqrt(hit.Distance2));
    fit.MeanMm += distances.back();
    fit.MaxMm = std::max(fit.MaxMm, distances.back());
  }
  fit.Vertices = distances.size();
  if (distances.empty()) return fit;
  fit.MeanMm /= double(distances.size());
  fit.P95Mm = NearestRankPercentile(std::move(distances), 0.95);
  return fit;
}

}  // namespace rp
