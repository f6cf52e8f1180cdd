#include "rpLabelComparison.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <vtkDataArray.h>
#include <vtkPointData.h>

namespace rp {
namespace {

using Index = std::array<int, 3>;

struct Grid {
  int Dims[3] = {0, 0, 0};
  size_t Size() const { return size_t(this->Dims[0]) * this->Dims[1] * this->Dims[2]; }
  size_t Offset(int i, int j, int k) const { return (size_t(k) * this->Dims[1] + j) * this->Dims[0] + i; }
};

std::vector<int> Labels(const ImageVolume& v, Grid& grid) {
  v.Image->GetDimensions(grid.Dims);
  std::vector<int> out(grid.Size());
  vtkDataArray* scalars = v.Image->GetPointData()->GetScalars();
  for (size_t n = 0; n < out.size(); ++n) out[n] = static_cast<int>(std::lround(scalars->GetComponent(vtkIdType(n), 0)));
  return out;
}

bool SameGeometry(const ImageVolume& a, const ImageVolume& b, const Grid& ga, const Grid& gb) {
  for (int d = 0; d < 3; ++d)
    if (ga.Dims[d] != gb.Dims[d]) return false;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a.IJKToRAS->GetElement(r, c) - b.IJKToRAS->GetElement(r, c)) > 1e-4) return false;
  return true;
}

// The truth's label at each voxel centre of the test grid (nearest truth voxel; 0 outside).
std::vector<int> SampleOnto(const ImageVolume& test, const Grid& grid, const ImageVolume& truth,
                            const Grid& truthGrid, const std::vector<int>& truthLabels) {
  vtkNew<vtkMatrix4x4> rasToTruth, testToTruth;
  vtkMatrix4x4::Invert(truth.IJKToRAS, rasToTruth);
  vtkMatrix4x4::Multiply4x4(rasToTruth, test.IJKToRAS, testToTruth);
  std::vector<int> out(grid.Size(), 0);
  for (int k = 0; k < grid.Dims[2]; ++k)
    for (int j = 0; j < grid.Dims[1]; ++j)
      for (int i = 0; i < grid.Dims[0]; ++i) {
        const double p[4] = {double(i), double(j), double(k), 1.0};
        double q[4];
        testToTruth->MultiplyPoint(p, q);
        Index t;
        bool inside = true;
        for (int d = 0; d < 3; ++d) {
          t[d] = int(std::lround(q[d]));
          inside &= t[d] >= 0 && t[d] < truthGrid.Dims[d];
        }
        if (inside) out[grid.Offset(i, j, k)] = truthLabels[truthGrid.Offset(t[0], t[1], t[2])];
      }
  return out;
}

// Voxels of the mask with a 6-neighbour outside it (the grid's border counts as outside).
std::vector<char> Boundary(const std::vector<char>& mask, const Grid& g) {
  std::vector<char> edge(mask.size(), 0);
  for (int k = 0; k < g.Dims[2]; ++k)
    for (int j = 0; j < g.Dims[1]; ++j)
      for (int i = 0; i < g.Dims[0]; ++i) {
        if (!mask[g.Offset(i, j, k)]) continue;
        const int n[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : n) {
          const bool outside = q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= g.Dims[0] || q[1] >= g.Dims[1] ||
                               q[2] >= g.Dims[2] || !mask[g.Offset(q[0], q[1], q[2])];
          if (outside) {
            edge[g.Offset(i, j, k)] = 1;
            break;
          }
        }
      }
  return edge;
}

// Squared distance (mm²) from every voxel to the nearest set voxel: Felzenszwalb & Huttenlocher's
// separable transform, one pass per axis with that axis's spacing.
std::vector<double> SquaredDistance(const std::vector<char>& set, const Grid& g, const double spacing[3]) {
  const double inf = std::numeric_limits<double>::max() / 4;
  std::vector<double> d(set.size());
  for (size_t n = 0; n < set.size(); ++n) d[n] = set[n] ? 0.0 : inf;
  const int longest = std::max({g.Dims[0], g.Dims[1], g.Dims[2]});
  std::vector<double> f(longest), out(longest), z(longest + 1);
  std::vector<int> v(longest);
  for (int axis = 0; axis < 3; ++axis) {
    const int n = g.Dims[axis], a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const double s = spacing[axis];
    for (int u = 0; u < g.Dims[a1]; ++u)
      for (int w = 0; w < g.Dims[a2]; ++w) {
        auto at = [&](int q) {
          int ijk[3];
          ijk[axis] = q;
          ijk[a1] = u;
          ijk[a2] = w;
          return g.Offset(ijk[0], ijk[1], ijk[2]);
        };
        for (int q = 0; q < n; ++q) f[q] = d[at(q)];
        // Lower envelope of the parabolas (q·s - p·s)² + f(p).
        int k = -1;
        for (int q = 0; q < n; ++q) {
          if (f[q] >= inf) continue;
          double sq = 0;
          while (k >= 0) {
            const int p = v[k];
            sq = ((f[q] + q * q * s * s) - (f[p] + p * p * s * s)) / (2 * s * (q - p));
            if (sq <= z[k]) {
              --k;
              continue;
            }
            break;
          }
          ++k;
          v[k] = q;
          z[k] = k == 0 ? -inf : sq;
          z[k + 1] = inf;
        }
        if (k < 0) continue;  // nothing set on this line
        int j = 0;
        for (int q = 0; q < n; ++q) {
          while (z[j + 1] < q * s) ++j;
          const double dq = (q - v[j]) * s;
          out[q] = dq * dq + f[v[j]];
        }
        for (int q = 0; q < n; ++q) d[at(q)] = out[q];
      }
  }
  return d;
}

// Distances (mm) from each boundary voxel of one label to the other's boundary, both ways.
std::vector<double> SurfaceDistances(const std::vector<char>& a, const std::vector<char>& b, const Grid& g,
                                     const double spacing[3]) {
  const auto edgeA = Boundary(a, g), edgeB = Boundary(b, g);
  const auto toB = SquaredDistance(edgeB, g, spacing), toA = SquaredDistance(edgeA, g, spacing);
  std::vector<double> distances;
  for (size_t n = 0; n < a.size(); ++n) {
    if (edgeA[n]) distances.push_back(std::sqrt(toB[n]));
    if (edgeB[n]) distances.push_back(std::sqrt(toA[n]));
  }
  return distances;
}

}  // namespace

bool CompareLabels(const ImageVolume& test, const ImageVolume& truth, std::vector<int> labels,
                   LabelComparison& result, std::string& error) {
  result = LabelComparison();
  if (test.Empty() || truth.Empty()) {
    error = "an image to compare is empty";
    return false;
  }
  Grid grid, truthGrid;
  const std::vector<int> testLabels = Labels(test, grid);
  std::vector<int> truthLabels = Labels(truth, truthGrid);
  if (!SameGeometry(test, truth, grid, truthGrid)) {
    truthLabels = SampleOnto(test, grid, truth, truthGrid, truthLabels);
    result.TruthResampled = true;
  }
  std::set<int> present(testLabels.begin(), testLabels.end()), truthPresent(truthLabels.begin(), truthLabels.end());
  present.erase(0);
  truthPresent.erase(0);
  if (labels.empty()) labels.assign(present.begin(), present.end());
  if (labels.empty()) {
    error = "the segmentation has no labelled voxel";
    return false;
  }
  if (truthPresent.empty()) {
    error = "the truth labelmap has no labelled voxel (on the segmentation's grid)";
    return false;
  }
  double spacing[3];
  test.GetSpacing(spacing);
  std::set<int> matched;
  for (int label : labels) {
    LabelScore score;
    score.Label = label;
    std::map<int, long long> overlap;
    for (size_t n = 0; n < testLabels.size(); ++n) {
      if (testLabels[n] != label) continue;
      ++score.Voxels;
      if (truthLabels[n] != 0) ++overlap[truthLabels[n]];
    }
    for (const auto& [truthLabel, count] : overlap)
      if (count > score.OverlapVoxels) score.TruthLabel = truthLabel, score.OverlapVoxels = count;
    if (score.TruthLabel != 0) {
      matched.insert(score.TruthLabel);
      std::vector<char> a(testLabels.size()), b(testLabels.size());
      for (size_t n = 0; n < testLabels.size(); ++n) {
        a[n] = testLabels[n] == label;
        b[n] = truthLabels[n] == score.TruthLabel;
        score.TruthVoxels += b[n];
      }
      score.Dice = 2.0 * double(score.OverlapVoxels) / double(score.Voxels + score.TruthVoxels);
      auto distances = SurfaceDistances(a, b, grid, spacing);
      if (!distances.empty()) {
        double sum = 0;
        for (double d : distances) sum += d;
        score.MeanSurfaceDistanceMm = sum / double(distances.size());
        const size_t p95 = std::min(distances.size() - 1, size_t(std::ceil(0.95 * double(distances.size()))) - 1);
        std::nth_element(distances.begin(), distances.begin() + long(p95), distances.end());
        score.Hausdorff95Mm = distances[p95];
        score.HausdorffMm = *std::max_element(distances.begin(), distances.end());
      }
    }
    result.Scores.push_back(score);
  }
  for (int t : truthPresent)
    if (!matched.count(t)) result.UnmatchedTruth.push_back(t);
  return true;
}

}  // namespace rp
