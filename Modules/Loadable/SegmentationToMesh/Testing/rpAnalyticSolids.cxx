#include "rpAnalyticSolids.h"

#include <algorithm>
#include <cmath>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkNew.h>

#include "vtkRPSegmentationNode.h"

namespace rp::test {

namespace {
constexpr double Pi = 3.14159265358979323846;

std::vector<std::array<double, 3>> FibonacciSphere(int n) {
  std::vector<std::array<double, 3>> points;
  const double golden = Pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), t = golden * i;
    points.push_back({r * std::cos(t), r * std::sin(t), z});
  }
  return points;
}
}  // namespace

AnalyticSolid Sphere(const std::array<double, 3>& c, double radius) {
  AnalyticSolid s;
  s.Name = "sphere";
  s.SDF = [c, radius](const double p[3]) {
    return std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2])) -
           radius;
  };
  s.Volume = 4.0 / 3.0 * Pi * radius * radius * radius;
  for (const auto& u : FibonacciSphere(4000)) s.SurfacePoints.push_back({c[0] + radius * u[0], c[1] + radius * u[1], c[2] + radius * u[2]});
  return s;
}

AnalyticSolid Ellipsoid(const std::array<double, 3>& c, const std::array<double, 3>& e) {
  AnalyticSolid s;
  s.Name = "ellipsoid";
  // Exact distance: the closest point is x_i = p_i e_i² / (e_i² + t) with t the root of
  // sum (p_i e_i / (e_i² + t))² = 1 on t > -min(e_i²) (monotone there): bisection.
  s.SDF = [c, e](const double q[3]) {
    double p[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = q[i] - c[static_cast<size_t>(i)];
      if (std::abs(p[i]) < 1e-9) p[i] = 1e-9;  // off the symmetry planes
    }
    double inside = 0;
    for (int i = 0; i < 3; ++i) inside += (p[i] / e[static_cast<size_t>(i)]) * (p[i] / e[static_cast<size_t>(i)]);
    const double minE2 = std::min({e[0] * e[0], e[1] * e[1], e[2] * e[2]});
    auto F = [&](double t) {
      double sum = 0;
      for (int i = 0; i < 3; ++i) {
        const double ei = e[static_cast<size_t>(i)];
        const double v = p[i] * ei / (ei * ei + t);
        sum += v * v;
      }
      return sum - 1.0;
    };
    double lo = -minE2 + 1e-12, hi = std::max(1.0, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) * 100.0);
    while (F(hi) > 0) hi *= 2;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (F(mid) > 0 ? lo : hi) = mid;
    }
    const double t = 0.5 * (lo + hi);
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double ei = e[static_cast<size_t>(i)];
      const double x = p[i] * ei * ei / (ei * ei + t);
      d2 += (x - p[i]) * (x - p[i]);
    }
    return inside < 1 ? -std::sqrt(d2) : std::sqrt(d2);
  };
  s.Volume = 4.0 / 3.0 * Pi * e[0] * e[1] * e[2];
  for (const auto& u : FibonacciSphere(6000)) s.SurfacePoints.push_back({c[0] + e[0] * u[0], c[1] + e[1] * u[1], c[2] + e[2] * u[2]});
  return s;
}

AnalyticSolid Torus(const std::array<double, 3>& c, double R, double r) {
  AnalyticSolid s;
  s.Name = "torus";
  s.SDF = [c, R, r](const double p[3]) {
    const double x = p[0] - c[0], y = p[1] - c[1], z = p[2] - c[2];
    const double q = std::sqrt(x * x + y * y) - R;
    return std::sqrt(q * q + z * z) - r;
  };
  s.Volume = 2.0 * Pi * Pi * R * r * r;
  const int nu = 160, nv = 60;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * Pi * i / nu, v = 2 * Pi * j / nv;
      s.SurfacePoints.push_back({c[0] + (R + r * std::cos(v)) * std::cos(u), c[1] + (R + r * std::cos(v)) * std::sin(u),
                                 c[2] + r * std::sin(v)});
    }
  return s;
}

AnalyticSolid Box(const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  AnalyticSolid s;
  s.Name = "box";
  s.SDF = [lo, hi](const double p[3]) {
    double outside = 0, inside = -1e300;
    for (size_t a = 0; a < 3; ++a) {
      const double c = 0.5 * (lo[a] + hi[a]), h = 0.5 * (hi[a] - lo[a]);
      const double d = std::abs(p[a] - c) - h;
      outside += std::max(d, 0.0) * std::max(d, 0.0);
      inside = std::max(inside, d);
    }
    return outside > 0 ? std::sqrt(outside) : inside;
  };
  s.Volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  // Points on the six faces, about 0.25 mm apart.
  for (size_t a = 0; a < 3; ++a) {
    const size_t b = (a + 1) % 3, c = (a + 2) % 3;
    const int nb = std::max(2, static_cast<int>((hi[b] - lo[b]) / 0.25)), nc = std::max(2, static_cast<int>((hi[c] - lo[c]) / 0.25));
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i <= nb; ++i)
        for (int j = 0; j <= nc; ++j) {
          std::array<double, 3> p;
          p[a] = side ? hi[a] : lo[a];
          p[b] = lo[b] + (hi[b] - lo[b]) * i / nb;
          p[c] = lo[c] + (hi[c] - lo[c]) * j / nc;
          s.SurfacePoints.push_back(p);
        }
  }
  return s;
}

vtkSmartPointer<vtkRPSegmentationNode> Rasterize(const AnalyticSolid& solid, const std::array<int, 3>& dims,
                                                 const std::array<double, 3>& spacing,
                                                 const std::array<double, 3>& origin, int label,
                                                 const std::string& tissueClass) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const double p[3] = {origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2]};
        *v++ = solid.SDF(p) < 0 ? static_cast<unsigned char>(label) : 0;
      }
  auto node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  node->SetImageData(image);
  const double directions[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  node->SetGeometry(spacing.data(), origin.data(), directions);
  vtkRPSegmentationNode::Segment s;
  s.ID = solid.Name;
  s.Name = solid.Name;
  s.LabelValue = label;
  s.TissueClass = tissueClass;
  node->SetSegment(s);
  return node;
}

long CountLabel(vtkRPSegmentationNode* node, int label) {
  vtkImageData* image = node->GetImageData();
  long count = 0;
  for (vtkIdType n = 0; n < image->GetNumberOfPoints(); ++n)
    count += static_cast<int>(image->GetPointData()->GetScalars()->GetComponent(n, 0)) == label;
  return count;
}

double Dice(vtkRPSegmentationNode* a, int labelA, vtkRPSegmentationNode* b, int labelB) {
  vtkDataArray* sa = a->GetImageData()->GetPointData()->GetScalars();
  vtkDataArray* sb = b->GetImageData()->GetPointData()->GetScalars();
  long na = 0, nb = 0, both = 0;
  for (vtkIdType n = 0; n < sa->GetNumberOfTuples(); ++n) {
    const bool ia = static_cast<int>(sa->GetComponent(n, 0)) == labelA;
    const bool ib = static_cast<int>(sb->GetComponent(n, 0)) == labelB;
    na += ia, nb += ib, both += ia && ib;
  }
  return na + nb > 0 ? 2.0 * both / static_cast<double>(na + nb) : 1.0;
}

}  // namespace rp::test
