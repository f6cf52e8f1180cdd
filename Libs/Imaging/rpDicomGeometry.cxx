#include "rpDicomGeometry.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomSeries.h"
#include "rpDicomTransferSyntax.h"

namespace rp {

std::string OrientationName(const double iop[6]) {
  const double n[3] = {iop[1] * iop[5] - iop[2] * iop[4], iop[2] * iop[3] - iop[0] * iop[5],
                       iop[0] * iop[4] - iop[1] * iop[3]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (length < 1e-6) return "degenerate";
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) > std::abs(n[axis])) axis = a;
  const char* names[3] = {"sagittal", "coronal", "axial"};  // normal along x (L), y (P), z (S)
  const double degrees = std::acos(std::min(1.0, std::abs(n[axis]) / length)) * 180.0 / M_PI;
  if (degrees < 0.5) return names[axis];
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "oblique " << names[axis] << " (" << degrees << "°)";
  return s.str();
}

namespace dicom {

namespace {

void Cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
double Dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

bool SameStack(const SliceHeader& a, const SliceHeader& b) {
  if (a.Rows != b.Rows || a.Columns != b.Columns || a.HasOrientation != b.HasOrientation) return false;
  for (int i = 0; i < 6; ++i)
    if (std::abs(a.Orientation[i] - b.Orientation[i]) > 1e-3) return false;
  return std::abs(a.PixelSpacing[0] - b.PixelSpacing[0]) <= 1e-4 &&
         std::abs(a.PixelSpacing[1] - b.PixelSpacing[1]) <= 1e-4;
}

std::vector<std::vector<SliceHeader>> SplitIntoStacks(std::vector<SliceHeader> headers) {
  std::vector<std::vector<SliceHeader>> stacks;
  for (SliceHeader& h : headers) {
    auto it = std::find_if(stacks.begin(), stacks.end(),
                           [&](const std::vector<SliceHeader>& s) { return SameStack(s.front(), h); });
    if (it == stacks.end()) {
      stacks.emplace_back();
      it = stacks.end() - 1;
    }
    it->push_back(std::move(h));
  }
  return stacks;
}

std::vector<std::string> DistinctFiles(const std::vector<SliceHeader>& headers) {
  std::vector<std::string> files;
  for (const SliceHeader& h : headers)
    if (files.empty() || files.back() != h.File) files.push_back(h.File);
  return files;
}

SeriesGeometry AnalyzeGeometry(const std::vector<SliceHeader>& headers, double tolerance) {
  SeriesGeometry g;
  if (headers.empty()) {
    g.Problem = "no image files";
    return g;
  }
  const SliceHeader& first = headers.front();
  for (const SliceHeader& h : headers) {
    if (!h.HeaderProblem.empty()) {
      g.Problem = h.HeaderProblem;
      return g;
    }
    const TransferSyntaxInfo* syntax = FindTransferSyntax(h.TransferSyntax);
    if (!syntax) {
      g.Problem = "transfer syntax " + h.TransferSyntax + " of " + Name(h.File) +
                  " is not one the reader decodes (see the README's table of transfer syntaxes)";
      return g;
    }
    if (headers.size() > 1 && !h.HasPosition) {
      g.Problem = "ImagePositionPatient missing in " + Name(h.File) + ": slices cannot be ordered";
      return g;
    }
  }
  double row[3] = {first.Orientation[0], first.Orientation[1], first.Orientation[2]};
  double col[3] = {first.Orientation[3], first.Orientation[4], first.Orientation[5]};
  Cross(row, col, g.Normal);
  const double n = std::sqrt(Dot3(g.Normal, g.Normal));
  if (n < 1e-3) {
    g.Problem = "degenerate ImageOrientationPatient in " + Name(first.File);
    return g;
  }
  for (double& v : g.Normal) v /= n;

  g.Order.resize(headers.size());
  for (size_t i = 0; i < headers.size(); ++i) g.Order[i] = i;
  std::vector<double> along(headers.size());
  for (size_t i = 0; i < headers.size(); ++i) along[i] = Dot3(headers[i].Position, g.Normal);
  std::stable_sort(g.Order.begin(), g.Order.end(), [&](size_t a, size_t b) { return along[a] < along[b]; });
  for (size_t i : g.Order) g.Positions.push_back(along[i]);

  auto where = [&](size_t index) {
    const SliceHeader& h = headers[index];
    return h.Frames > 1 ? Name(h.File) + " frame " + std::to_string(h.Frame + 1) : Name(h.File);
  };
  if (headers.size() == 1) {
    g.Spacing = first.SpacingBetweenSlices > 0 ? first.SpacingBetweenSlices
                                               : (first.SliceThickness > 0 ? first.SliceThickness : 1.0);
    g.MinGap = g.Spacing;
    return g;
  }
  std::vector<double> gaps;
  for (size_t k = 1; k < g.Positions.size(); ++k) {
    const double gap = g.Positions[k] - g.Positions[k - 1];
    if (gap < 1e-4) {
      g.Problem = "two slices at the same position " + Fmt(g.Positions[k], 3) + " mm (" + where(g.Order[k - 1]) +
                  ", " + where(g.Order[k]) +
                  "): several acquisitions, echoes or time points in one series are not supported";
      return g;
    }
    gaps.push_back(gap);
  }
  // Gantry tilt: positions must move along the normal only.
  const SliceHeader& h0 = headers[g.Order.front()];
  const SliceHeader& hn = headers[g.Order.back()];
  double d[3] = {hn.Position[0] - h0.Position[0], hn.Position[1] - h0.Position[1], hn.Position[2] - h0.Position[2]};
  const double axial = Dot3(d, g.Normal);
  double lateral[3] = {d[0] - axial * g.Normal[0], d[1] - axial * g.Normal[1], d[2] - axial * g.Normal[2]};
  const double lateralLength = std::sqrt(Dot3(lateral, lateral));
  if (lateralLength > 0.01 + 1e-3 * std::abs(axial)) {
    const double degrees = std::atan2(lateralLength, std::abs(axial)) * 180.0 / M_PI;
    g.Problem = "gantry tilt of " + Fmt(degrees, 1) +
                " degrees (slice positions do not follow the slice normal) is not supported";
    return g;
  }
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  g.Spacing = sorted[sorted.size() / 2];
  g.MinGap = sorted.front();
  for (size_t k = 0; k < gaps.size(); ++k) {
    if (std::abs(gaps[k] - g.Spacing) > std::max(1e-3, tolerance * g.Spacing)) {
      const long multiple = std::lround(gaps[k] / g.Spacing);
      const bool missing = multiple >= 2 && std::abs(gaps[k] - multiple * g.Spacing) < std::max(1e-3, tolerance * g.Spacing);
      std::string between = "between positions " + Fmt(g.Positions[k]) + " mm (" + where(g.Order[k]) + ") and " +
                            Fmt(g.Positions[k + 1]) + " mm (" + where(g.Order[k + 1]) + "): gap " + Fmt(gaps[k]) +
                            " mm, expected " + Fmt(g.Spacing) + " mm";
      g.Irregular = true;
      g.IrregularMessage = missing ? std::to_string(multiple - 1) + " missing slice(s) " + between
                                   : "uneven slice spacing " + between;
      break;
    }
  }
  return g;
}

void StackMatrix(const SliceHeader& h0, const SeriesGeometry& g, double spacing, double firstPosition,
                 double ijkToLPS[16]) {
  double axes[3][3] = {{h0.Orientation[0], h0.Orientation[1], h0.Orientation[2]},
                       {h0.Orientation[3], h0.Orientation[4], h0.Orientation[5]},
                       {g.Normal[0], g.Normal[1], g.Normal[2]}};
  for (int c = 0; c < 2; ++c) {
    const double n = std::sqrt(Dot3(axes[c], axes[c]));
    for (double& v : axes[c]) v /= n;
  }
  const double spacings[3] = {h0.PixelSpacing[1], h0.PixelSpacing[0], spacing};
  double origin[3] = {h0.Position[0], h0.Position[1], h0.Position[2]};
  const double shift = firstPosition - g.Positions.front();
  for (int r = 0; r < 3; ++r) origin[r] += shift * g.Normal[r];
  for (int i = 0; i < 16; ++i) ijkToLPS[i] = i == 15 ? 1.0 : 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) ijkToLPS[4 * r + c] = axes[c][r] * spacings[c];
    ijkToLPS[4 * r + 3] = origin[r];
  }
}

vtkSmartPointer<vtkImageData> ResampleAlongNormal(vtkImageData* stack, const SeriesGeometry& g,
                                                  std::vector<double>& positions, double& spacing) {
  int dims[3];
  stack->GetDimensions(dims);
  const size_t sliceSize = static_cast<size_t>(dims[0]) * dims[1];
  spacing = g.MinGap;
  const double length = g.Positions.back() - g.Positions.front();
  const int n = static_cast<int>(std::lround(length / spacing)) + 1;
  spacing = n > 1 ? length / (n - 1) : spacing;
  positions.clear();
  for (int k = 0; k < n; ++k) positions.push_back(g.Positions.front() + k * spacing);
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims[0], dims[1], n);
  image->AllocateScalars(VTK_FLOAT, 1);
  float* dst = static_cast<float*>(image->GetScalarPointer());
  vtkDataArray* src = stack->GetPointData()->GetScalars();
  size_t below = 0;
  for (int k = 0; k < n; ++k) {
    const double p = positions[k];
    while (below + 2 < g.Positions.size() && g.Positions[below + 1] <= p) ++below;
    const size_t a = below, b = std::min(below + 1, g.Positions.size() - 1);
    const double t = b != a ? std::clamp((p - g.Positions[a]) / (g.Positions[b] - g.Positions[a]), 0.0, 1.0) : 0.0;
    for (size_t i = 0; i < sliceSize; ++i) {
      const double va = src->GetComponent(static_cast<vtkIdType>(a * sliceSize + i), 0);
      const double vb = src->GetComponent(static_cast<vtkIdType>(b * sliceSize + i), 0);
      dst[static_cast<size_t>(k) * sliceSize + i] = static_cast<float>((1.0 - t) * va + t * vb);
    }
  }
  return image;
}

}  // namespace dicom
}  // namespace rp
