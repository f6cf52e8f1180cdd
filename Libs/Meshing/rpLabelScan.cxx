#include "rpLabelScan.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSMPThreadLocal.h>

#include "rpParallelFor.h"

namespace rp {

namespace {

// Calls visit(local, row, j, k) for every row of the volume, the slices spread over VTK's SMP
// threads, each with its thread's `locals` entry.
template <typename T, typename Local, typename Visit>
void ForEachRow(const T* voxels, const int dims[3], vtkSMPThreadLocal<Local>& locals, Visit&& visit) {
  ParallelFor(0, dims[2], [&](vtkIdType k0, vtkIdType k1) {
    Local& l = locals.Local();
    for (vtkIdType kk = k0; kk < k1; ++kk) {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < dims[1]; ++j) visit(l, voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0], j, k);
    }
  });
}

// A thread's share of one label's bounds. Outside the templates below, as the other per-thread
// records here: vtkSMPThreadLocal of a type local to a function templated on the voxel type is
// compiled, with its three SMP back-ends, once per type.
struct BoundsLocal {
  int Lo[3] = {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  int Hi[3] = {-1, -1, -1};
  long Count = 0;
};

template <typename T>
void FindBounds(const T* voxels, const int dims[3], long label, LabelBounds& b) {
  const T value = static_cast<T>(label);
  using Local = BoundsLocal;
  vtkSMPThreadLocal<Local> locals;
  ForEachRow(voxels, dims, locals, [&](Local& l, const T* row, int j, int k) {
    // Count first (a branch-free loop the compiler vectorizes), then find the ends only in
    // rows that hold the label: most rows of a large labelmap do not.
    long count = 0;
    for (int i = 0; i < dims[0]; ++i) count += row[i] == value;
    if (count == 0) return;
    l.Count += count;
    int first = 0, last = dims[0] - 1;
    while (row[first] != value) ++first;
    while (row[last] != value) --last;
    l.Lo[0] = std::min(l.Lo[0], first), l.Hi[0] = std::max(l.Hi[0], last);
    l.Lo[1] = std::min(l.Lo[1], j), l.Hi[1] = std::max(l.Hi[1], j);
    l.Lo[2] = std::min(l.Lo[2], k), l.Hi[2] = std::max(l.Hi[2], k);
  });
  LabelBounds result;
  for (int a = 0; a < 3; ++a) result.Lo[a] = std::numeric_limits<int>::max(), result.Hi[a] = -1;
  for (const Local& l : locals) {
    result.Count += l.Count;
    for (int a = 0; a < 3; ++a) result.Lo[a] = std::min(result.Lo[a], l.Lo[a]), result.Hi[a] = std::max(result.Hi[a], l.Hi[a]);
  }
  b = result;
}

// Every label's bounds of a one-byte labelmap in one pass: one read of the volume serves all its
// segments (a pass per label read 78 M voxels for each). Zero is the background; a row is read
// as runs of one value, eight voxels at a time while a whole word holds the run's value.
struct AllBounds {
  std::array<LabelBounds, 256> ByByte;  // indexed by the voxel's byte
};

// A thread's share of every one-byte label's bounds.
struct AllBoundsLocal {
  std::array<std::array<int, 3>, 256> Lo, Hi;
  std::array<long, 256> Count{};
  AllBoundsLocal() {
    for (auto& lo : Lo) lo.fill(std::numeric_limits<int>::max());
    for (auto& hi : Hi) hi.fill(-1);
  }
};

template <typename T>
void FindAllBounds(const T* voxels, const int dims[3], AllBounds& all) {
  static_assert(sizeof(T) == 1, "one-byte labels");
  using Local = AllBoundsLocal;
  vtkSMPThreadLocal<Local> locals;
  ForEachRow(voxels, dims, locals, [&](Local& l, const T* voxelRow, int j, int k) {
    // Runs of one value, eight voxels at a time while a whole word holds it.
    const unsigned char* row = reinterpret_cast<const unsigned char*>(voxelRow);
    const int n = dims[0];
    int i = 0;
    while (i < n) {
      const unsigned char v = row[i];
      const uint64_t pattern = 0x0101010101010101ULL * v;
      const int start = i;
      while (i + 8 <= n) {
        uint64_t word;
        std::memcpy(&word, row + i, sizeof(word));
        if (word != pattern) break;
        i += 8;
      }
      while (i < n && row[i] == v) ++i;
      if (!v) continue;
      l.Count[v] += i - start;
      auto& lo = l.Lo[v];
      auto& hi = l.Hi[v];
      lo[0] = std::min(lo[0], start), hi[0] = std::max(hi[0], i - 1);
      lo[1] = std::min(lo[1], j), hi[1] = std::max(hi[1], j);
      lo[2] = std::min(lo[2], k), hi[2] = std::max(hi[2], k);
    }
  });
  for (auto& b : all.ByByte) {
    b = LabelBounds();
    for (int a = 0; a < 3; ++a) b.Lo[a] = std::numeric_limits<int>::max(), b.Hi[a] = -1;
  }
  for (const Local& l : locals) {
    for (size_t v = 1; v < 256; ++v) {
      if (!l.Count[v]) continue;
      LabelBounds& b = all.ByByte[v];
      b.Count += l.Count[v];
      for (int a = 0; a < 3; ++a) b.Lo[a] = std::min(b.Lo[a], l.Lo[v][a]), b.Hi[a] = std::max(b.Hi[a], l.Hi[v][a]);
    }
  }
}

// A label's bounds, scanned once per labelmap version: a level of detail contours the same label
// on several grids, and each scan reads the whole volume (78 M voxels for 512x512x300).

template <typename T>
void ExtractMask(const T* voxels, const int dims[3], long label, const int start[3], const int size[3],
                 unsigned char* mask) {
  const T value = static_cast<T>(label);
  ParallelFor(0, size[2], [&](vtkIdType k0, vtkIdType k1) {
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
  // One-byte labels other than 0: every label's bounds from one pass, kept for the next segment.
  const int type = labelmap->GetScalarType();
  const bool oneByte = type == VTK_UNSIGNED_CHAR || type == VTK_SIGNED_CHAR || type == VTK_CHAR;
  const unsigned char byte = static_cast<unsigned char>(label);  // the voxel byte static_cast<T>(label) is
  if (oneByte && byte != 0) {
    struct AllEntry {
      const void* Image = nullptr;
      vtkMTimeType Time = 0;
      AllBounds Bounds;
    };
    thread_local AllEntry all;
    if (all.Image != labelmap || all.Time != time) {
      if (type == VTK_UNSIGNED_CHAR)
        FindAllBounds(static_cast<const unsigned char*>(labelmap->GetScalarPointer()), dims, all.Bounds);
      else
        FindAllBounds(static_cast<const signed char*>(labelmap->GetScalarPointer()), dims, all.Bounds);
      all.Image = labelmap, all.Time = time;
    }
    return all.Bounds.ByByte[byte];
  }
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
