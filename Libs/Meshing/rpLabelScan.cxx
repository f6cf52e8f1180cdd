#include "rpLabelScan.h"

#include <algorithm>
#include <array>
#include <limits>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

namespace rp {

namespace {

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

}  // namespace

LabelBounds CachedLabelBounds(vtkImageData* labelmap, long label) {
  struct Entry {
    const void* Image = nullptr;
    vtkMTimeType Time = 0;
    long Label = 0;
    LabelBounds Bounds;
  };
  thread_local std::array<Entry, 8> cache;
  thread_local size_t next = 0;
  int dims[3];
  labelmap->GetDimensions(dims);
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

bool HasIntegerScalars(vtkImageData* image) {
  switch (image->GetScalarType()) {
    case VTK_UNSIGNED_CHAR: case VTK_SIGNED_CHAR: case VTK_CHAR: case VTK_SHORT: case VTK_UNSIGNED_SHORT:
    case VTK_INT: case VTK_UNSIGNED_INT: case VTK_LONG: case VTK_UNSIGNED_LONG: case VTK_LONG_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      return true;
    default:
      return false;
  }
}


void ExtractLabelMask(vtkImageData* labelmap, long label, const int start[3], const int size[3], unsigned char* mask) {
  int dims[3];
  labelmap->GetDimensions(dims);
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(ExtractMask(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims, label, start, size, mask));
  }
}

}  // namespace rp
