#include "rpGaussianField.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include <vtkSMPThreadLocal.h>

#include "rpParallelFor.h"

namespace rp {

namespace {

// 1-D resampling weights: output o sits at input position start + o * step.
struct Kernel1D {
  std::vector<int> First, Count;   // first input index (relative to the input range) and tap count
  std::vector<size_t> Offset;      // into Weights
  std::vector<float> Weights;
  std::vector<float> Sum;          // the taps' weights summed in order: the output under all ones
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
    float sum = 0;
    for (int k = first; k <= last; ++k) {
      kernel.Weights.push_back(static_cast<float>(std::exp(-0.5 * (p - k) * (p - k) / (sigma * sigma)) / norm));
      sum += kernel.Weights.back();
    }
    kernel.Sum.push_back(sum);
  }
  return kernel;
}

// The runs of `value` in a row, as start, end (exclusive) pairs. One-byte labels are read eight
// at a time while a word holds no voxel of the label, or only such voxels.
template <typename T>
void FindRuns(const T* in, int n, T value, std::vector<int>& runs) {
  runs.clear();
  int i = 0;
  while (i < n) {
    if constexpr (sizeof(T) == 1) {
      const uint64_t pattern = 0x0101010101010101ULL * static_cast<unsigned char>(value);
      for (uint64_t word; i + 8 <= n; i += 8) {
        std::memcpy(&word, in + i, sizeof(word));
        const uint64_t x = word ^ pattern;  // a zero byte where the voxel is the label
        if ((x - 0x0101010101010101ULL) & ~x & 0x8080808080808080ULL) break;
      }
    }
    while (i < n && in[i] != value) ++i;
    if (i == n) break;
    runs.push_back(i);
    if constexpr (sizeof(T) == 1) {
      const uint64_t pattern = 0x0101010101010101ULL * static_cast<unsigned char>(value);
      for (uint64_t word; i + 8 <= n; i += 8) {
        std::memcpy(&word, in + i, sizeof(word));
        if (word != pattern) break;
      }
    }
    while (i < n && in[i] == value) ++i;
    runs.push_back(i);
  }
}

// Constrains the field at samples that sit on voxel centres: labelled voxels stay inside the
// surface, others outside. The blur smooths staircases; the constraint keeps one-voxel
// structures (a single voxel, a one-voxel-thin plate) that a blur alone would erase.
template <typename T>
void ConstrainAtVoxelCentres(const T* voxels, const int dims[3], T value, const double gridStart[3],
                             const double step[3], const int outDims[3], float* field) {
  const size_t nxo = static_cast<size_t>(outDims[0]);
  const size_t plane = nxo * static_cast<size_t>(outDims[1]);
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
  const float high = 0.5f + GaussianConstraintMargin, low = 0.5f - GaussianConstraintMargin;
  ParallelFor(0, outDims[2], [&](vtkIdType z0, vtkIdType z1) {
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

// Outputs [Lo, Hi) of a row may be non-zero; the rest are 0.
struct Span {
  int Lo = 0, Hi = 0;
  bool Empty() const { return this->Lo >= this->Hi; }
};

// A thread's buffers for the x and y passes. Outside GaussianResample: vtkSMPThreadLocal of a
// type local to a function templated on the voxel type compiles its SMP back-ends once per type.
struct SliceScratch {
  std::vector<float> A;
  std::vector<int> Runs;   // the row's runs of the label: start, end (exclusive), ...
  std::vector<Span> SpanA;  // A's row jj
};

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
  // The mask is binary and mostly constant: an output whose taps all read 0 is 0, one whose taps
  // all read 1 is its weights' sum (the same sum, in the same order, as the taps would give), and
  // rows or slices that are all 0 add nothing to the passes after them (x + w * 0 == x), nor do
  // the 0s of a row outside its span (the outputs from its first to its last that are not 0: a
  // row of A or B is written and read over its span only). Only outputs near the label's edges
  // take the taps: the field is bit for bit what the plain convolution gives.
  const size_t nxo = static_cast<size_t>(outDims[0]);
  const size_t nyo = static_cast<size_t>(outDims[1]);
  std::unique_ptr<float[]> B(new float[nxo * nyo * static_cast<size_t>(inDims[2])]);
  std::vector<char> sliceEmpty(static_cast<size_t>(inDims[2]));  // B's slice kk is all 0
  std::vector<Span> spanB(static_cast<size_t>(inDims[2]) * nyo);  // B's row (kk, oy)
  vtkSMPThreadLocal<SliceScratch> scratch;
  ParallelFor(0, inDims[2], [&](vtkIdType k0, vtkIdType k1) {
    SliceScratch& local = scratch.Local();
    std::vector<float>& A = local.A;
    A.resize(nxo * static_cast<size_t>(inDims[1]));
    local.SpanA.resize(static_cast<size_t>(inDims[1]));
    std::vector<int>& runs = local.Runs;
    for (vtkIdType kk = k0; kk < k1; ++kk) {
      bool sliceAny = false;
      for (int jj = 0; jj < inDims[1]; ++jj) {
        const T* in = voxels + (static_cast<size_t>(b.Lo[2] + kk) * dims[1] + (b.Lo[1] + jj)) * dims[0] + b.Lo[0];
        FindRuns(in, inDims[0], value, runs);
        float* out = A.data() + static_cast<size_t>(jj) * nxo;
        Span& span = local.SpanA[static_cast<size_t>(jj)];
        span = Span();
        if (runs.empty()) continue;
        sliceAny = true;
        int lo = static_cast<int>(nxo), hi = 0;
        // Outputs in order: their windows move right, so the first run that can reach one only
        // moves right too.
        size_t r = 0;
        for (size_t o = 0; o < nxo; ++o) {
          const int first = kx.First[o], count = kx.Count[o], last = first + count;
          while (r < runs.size() && runs[r + 1] <= first) r += 2;
          int labelled = 0;
          for (size_t q = r; q < runs.size() && runs[q] < last; q += 2)
            labelled += std::min(runs[q + 1], last) - std::max(runs[q], first);
          if (labelled == 0) {
            out[o] = 0.0f;
            continue;
          }
          lo = std::min(lo, static_cast<int>(o)), hi = static_cast<int>(o) + 1;
          if (labelled == count) {
            out[o] = kx.Sum[o];
          } else {
            // The taps that read 1, in order (w * 1 == w; the taps that read 0 add +0).
            const float* w = kx.Weights.data() + kx.Offset[o];
            float sum = 0;
            for (size_t q = r; q < runs.size() && runs[q] < last; q += 2)
              for (int i = std::max(runs[q], first), e = std::min(runs[q + 1], last); i < e; ++i) sum += w[i - first];
            out[o] = sum;
          }
        }
        span.Lo = lo, span.Hi = hi;
      }
      sliceEmpty[static_cast<size_t>(kk)] = !sliceAny;
      for (size_t oy = 0; oy < nyo; ++oy) {
        Span& span = spanB[static_cast<size_t>(kk) * nyo + oy];
        span = Span();
        span.Lo = static_cast<int>(nxo);
        for (int t = 0; t < ky.Count[oy]; ++t) {
          const Span& in = local.SpanA[static_cast<size_t>(ky.First[oy] + t)];
          if (!in.Empty()) span.Lo = std::min(span.Lo, in.Lo), span.Hi = std::max(span.Hi, in.Hi);
        }
        if (span.Empty()) continue;
        // Over the B row's span (the rows of A it reads are 0 outside it): per tap spans took
        // more bookkeeping than they saved.
        const size_t lo = static_cast<size_t>(span.Lo), hi = static_cast<size_t>(span.Hi);
        float* out = B.get() + (static_cast<size_t>(kk) * nyo + oy) * nxo;
        std::fill(out + lo, out + hi, 0.0f);
        const float* w = ky.Weights.data() + ky.Offset[oy];
        for (int t = 0; t < ky.Count[oy]; ++t) {
          if (local.SpanA[static_cast<size_t>(ky.First[oy] + t)].Empty()) continue;
          const float* in = A.data() + static_cast<size_t>(ky.First[oy] + t) * nxo;
          const float wt = w[t];
          for (size_t x = lo; x < hi; ++x) out[x] += wt * in[x];
        }
      }
    }
  });
  // Pass z: B → field[outX x outY x outZ].
  const size_t plane = nxo * nyo;
  ParallelFor(0, outDims[2], [&](vtkIdType z0, vtkIdType z1) {
    for (vtkIdType oz = z0; oz < z1; ++oz) {
      float* out = field + static_cast<size_t>(oz) * plane;
      std::fill(out, out + plane, 0.0f);
      const float* w = kz.Weights.data() + kz.Offset[static_cast<size_t>(oz)];
      for (int t = 0; t < kz.Count[static_cast<size_t>(oz)]; ++t) {
        const size_t k = static_cast<size_t>(kz.First[static_cast<size_t>(oz)] + t);
        if (sliceEmpty[k]) continue;
        const float wt = w[t];
        for (size_t oy = 0; oy < nyo; ++oy) {
          const Span& from = spanB[k * nyo + oy];
          if (from.Empty()) continue;
          const float* in = B.get() + (k * nyo + oy) * nxo;
          float* row = out + oy * nxo;
          const size_t lo = static_cast<size_t>(from.Lo), hi = static_cast<size_t>(from.Hi);
          for (size_t x = lo; x < hi; ++x) row[x] += wt * in[x];
        }
      }
    }
  });
  ConstrainAtVoxelCentres(voxels, dims, value, gridStart, step, outDims, field);
}

}  // namespace

void ResampleLabelGaussian(vtkImageData* labelmap, long label, const LabelBounds& b, const double gridStart[3],
                           const double step[3], const int outDims[3], const double sigma[3], float* field) {
  int dims[3];
  labelmap->GetDimensions(dims);
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(GaussianResample(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims, label, b,
                                      gridStart, step, outDims, sigma, field));
  }
}

}  // namespace rp
