// BVH and triangle-grid queries against brute force and closed forms; queries must not allocate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "rpAllocationCounter.h"
#include "rpBVH.h"
#include "rpTriangleGrid.h"

namespace {
rp::ClosestPointHit BruteClosest(const rp::TriangleMesh& m, const rp::Vec3& p) {
  rp::ClosestPointHit best;
  best.Distance2 = HUGE_VAL;
  for (size_t i = 0; i < m.Triangles.size(); ++i) {
    const auto& t = m.Triangles[i];
    double bary[3];
    const rp::Vec3 q = rp::BVH::ClosestPointOnTriangle(p, m.Points[t[0]], m.Points[t[1]], m.Points[t[2]], bary);
    const double d2 = rp::Norm2(q - p);
    if (d2 < best.Distance2) {
      best.Distance2 = d2;
      best.Point = q;
      best.Triangle = static_cast<uint32_t>(i);
    }
  }
  return best;
}
}  // namespace

TEST(TriangleMesh, SphereIsClosedWithOutwardNormals) {
  const rp::TriangleMesh m = rp::shapes::Sphere({1, 2, 3}, 10, 3);
  ASSERT_EQ(m.Triangles.size(), 20u * 64u);
  EXPECT_EQ(m.Points.size(), 10u * 64u + 2u);  // Euler: V = F/2 + 2
  for (size_t i = 0; i < m.Triangles.size(); ++i) {
    const auto& t = m.Triangles[i];
    const rp::Vec3 c = (m.Points[t[0]] + m.Points[t[1]] + m.Points[t[2]]) / 3.0 - rp::Vec3{1, 2, 3};
    EXPECT_GT(rp::Dot(m.FaceNormals[i], rp::Normalized(c)), 0.99);
  }
  for (size_t i = 0; i < m.Points.size(); ++i)  // vertex normals of an icosphere are radial
    EXPECT_NEAR(rp::Dot(m.VertexNormals[i], rp::Normalized(m.Points[i] - rp::Vec3{1, 2, 3})), 1.0, 1e-3);
  std::string error;
  EXPECT_TRUE(m.Validate(error)) << error;
}

TEST(TriangleMesh, BoxNormalsPointOut) {
  const rp::TriangleMesh m = rp::shapes::Box({0, 0, 0}, {2, 4, 6});
  for (size_t i = 0; i < m.Triangles.size(); ++i) {
    const auto& t = m.Triangles[i];
    const rp::Vec3 c = (m.Points[t[0]] + m.Points[t[1]] + m.Points[t[2]]) / 3.0 - rp::Vec3{1, 2, 3};
    EXPECT_GT(rp::Dot(m.FaceNormals[i], c), 0.0) << "triangle " << i;
  }
}

TEST(TriangleMesh, ValidateNamesTheProblem) {
  rp::TriangleMesh m = rp::shapes::Box({0, 0, 0}, {1, 1, 1});
  m.Triangles[3][1] = 99;
  std::string error;
  EXPECT_FALSE(m.Validate(error));
  EXPECT_NE(error.find("triangle 3"), std::string::npos) << error;
  m = rp::shapes::Box({0, 0, 0}, {1, 1, 1});
  m.Points[2].y = std::nan("");
  EXPECT_FALSE(m.Validate(error));
  EXPECT_NE(error.find("point 2"), std::string::npos) << error;
}

TEST(BVH, ClosestPointMatchesBruteForceAndSphereDistance) {
  const rp::Vec3 c{5, -3, 2};
  const double r = 20;
  const rp::TriangleMesh m = rp::shapes::Sphere(c, r, 4);
  rp::BVH bvh;
  bvh.Build(m);
  ASSERT_EQ(bvh.NumberOfTriangles(), m.Triangles.size());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-40, 40);
  // Chord sagitta bounds the distance error of a tessellated sphere: r(1-cos(edge/2r)).
  const double edge = r * 1.1071 / 16;  // icosahedron edge angle / 2^4 subdivisions
  const double sagitta = r * (1 - std::cos(edge / (2 * r))) * 2;
  for (int i = 0; i < 300; ++i) {
    const rp::Vec3 p = c + rp::Vec3{u(rng), u(rng), u(rng)};
    rp::ClosestPointHit hit;
    ASSERT_TRUE(bvh.ClosestPoint(p, HUGE_VAL, hit));
    const rp::ClosestPointHit brute = BruteClosest(m, p);
    EXPECT_NEAR(hit.Distance2, brute.Distance2, 1e-9 * (1 + brute.Distance2));
    EXPECT_NEAR(std::sqrt(hit.Distance2), std::fabs(rp::Norm(p - c) - r), sagitta + 0.05);
    const auto& t = m.Triangles[hit.Triangle];
    const rp::Vec3 q = m.Points[t[0]] * hit.Barycentric[0] + m.Points[t[1]] * hit.Barycentric[1] +
                       m.Points[t[2]] * hit.Barycentric[2];
    EXPECT_NEAR(rp::Norm(q - hit.Point), 0.0, 1e-9);
  }
  rp::ClosestPointHit hit;
  EXPECT_FALSE(bvh.ClosestPoint(c + rp::Vec3{0, 0, 2 * r}, 5.0, hit));  // nothing within 5 mm
  EXPECT_TRUE(bvh.ClosestPoint(c + rp::Vec3{0, 0, r + 4}, 5.0, hit));
}

TEST(BVH, SegmentFirstHitFrontAndBack) {
  const rp::TriangleMesh m = rp::shapes::Box({-10, -10, -1}, {10, 10, 0});  // 1 mm sheet
  rp::BVH bvh;
  bvh.Build(m);
  rp::SegmentHit hit;
  ASSERT_TRUE(bvh.FirstHit({1, 2, 5}, {1, 2, -5}, rp::BVH::Faces::FrontOnly, hit));
  EXPECT_NEAR(hit.T, 0.5, 1e-12);
  EXPECT_NEAR(hit.Point.z, 0.0, 1e-12);
  EXPECT_NEAR(m.FaceNormals[hit.Triangle].z, 1.0, 1e-12);
  // From inside going down: the bottom face is an exit (back face) for FrontOnly.
  EXPECT_FALSE(bvh.FirstHit({1, 2, -0.5}, {1, 2, -5}, rp::BVH::Faces::FrontOnly, hit));
  ASSERT_TRUE(bvh.FirstHit({1, 2, -0.5}, {1, 2, -5}, rp::BVH::Faces::Both, hit));
  EXPECT_NEAR(hit.Point.z, -1.0, 1e-12);
  // Through a shared edge (the diagonal of the top face) still hits.
  EXPECT_TRUE(bvh.FirstHit({3, 3, 1}, {3, 3, -0.5}, rp::BVH::Faces::FrontOnly, hit));
  EXPECT_TRUE(bvh.FirstHit({-3, 3, 1}, {-3, 3, -0.5}, rp::BVH::Faces::FrontOnly, hit));
  EXPECT_FALSE(bvh.FirstHit({11, 0, 1}, {11, 0, -5}, rp::BVH::Faces::Both, hit));
}

TEST(BVH, QueriesDoNotAllocate) {
  const rp::TriangleMesh m = rp::shapes::Sphere({0, 0, 0}, 10, 5);
  rp::BVH bvh;
  bvh.Build(m);
  rp::ClosestPointHit c;
  rp::SegmentHit s;
  const uint64_t before = rp::alloc::ThreadAllocations();
  int hits = 0;
  for (int i = 0; i < 1000; ++i) {
    const double a = 0.01 * i;
    hits += bvh.ClosestPoint({15 * std::cos(a), 15 * std::sin(a), 0.01 * i - 5}, HUGE_VAL, c);
    hits += bvh.FirstHit({0, 0, 0}, {20 * std::cos(a), 20 * std::sin(a), 3}, rp::BVH::Faces::Both, s);
  }
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
  EXPECT_EQ(hits, 2000);
  // The counter itself works: a vector allocates.
  std::vector<int> v(10);
  EXPECT_GT(rp::alloc::ThreadAllocations(), before);
}

TEST(BVH, EmptyAndDegenerateMeshes) {
  rp::BVH bvh;
  rp::TriangleMesh m;
  bvh.Build(m);
  rp::ClosestPointHit c;
  EXPECT_FALSE(bvh.ClosestPoint({0, 0, 0}, HUGE_VAL, c));
  m.Points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  m.Triangles = {{0, 1, 2}};  // zero area: skipped
  bvh.Build(m);
  EXPECT_TRUE(bvh.Empty());
}

TEST(BVH, RandomTriangleSoupMatchesBruteForce) {
  // Triangles of very different sizes, overlapping, some coincident centroids: the builder and
  // both queries must still agree with a scan over every triangle.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-50, 50), s(0.01, 8);
  rp::TriangleMesh m;
  for (int i = 0; i < 3000; ++i) {
    const rp::Vec3 c{u(rng), u(rng), i % 10 == 0 ? 0.0 : u(rng)};
    const double size = s(rng);
    const int32_t base = static_cast<int32_t>(m.Points.size());
    m.Points.push_back(c + rp::Vec3{u(rng), u(rng), u(rng)} * (size / 50));
    m.Points.push_back(c + rp::Vec3{u(rng), u(rng), u(rng)} * (size / 50));
    m.Points.push_back(c + rp::Vec3{u(rng), u(rng), u(rng)} * (size / 50));
    m.Triangles.push_back({base, base + 1, base + 2});
  }
  for (int i = 0; i < 50; ++i) {  // identical copies: equal Morton codes
    m.Triangles.push_back(m.Triangles[0]);
  }
  rp::BVH bvh;
  bvh.Build(m);
  for (int q = 0; q < 200; ++q) {
    const rp::Vec3 p{u(rng), u(rng), u(rng)};
    rp::ClosestPointHit hit;
    ASSERT_TRUE(bvh.ClosestPoint(p, HUGE_VAL, hit));
    EXPECT_NEAR(hit.Distance2, BruteClosest(m, p).Distance2, 1e-9);
    const rp::Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    double bestT = 2;
    for (const auto& t : m.Triangles) {
      // Brute-force segment test (Möller–Trumbore) for the reference.
      const rp::Vec3 e1 = m.Points[t[1]] - m.Points[t[0]], e2 = m.Points[t[2]] - m.Points[t[0]], d = b - a;
      const rp::Vec3 pv = rp::Cross(d, e2);
      const double det = rp::Dot(e1, pv);
      if (det == 0) continue;
      const rp::Vec3 tv = a - m.Points[t[0]];
      const double uu = rp::Dot(tv, pv) / det;
      if (uu < 0 || uu > 1) continue;
      const rp::Vec3 qv = rp::Cross(tv, e1);
      const double vv = rp::Dot(d, qv) / det, tt = rp::Dot(e2, qv) / det;
      if (vv < 0 || uu + vv > 1 || tt < 0 || tt > 1) continue;
      bestT = std::min(bestT, tt);
    }
    rp::SegmentHit sh;
    const bool found = bvh.FirstHit(a, b, rp::BVH::Faces::Both, sh);
    EXPECT_EQ(found, bestT <= 1) << "query " << q;
    if (found && bestT <= 1) {
      EXPECT_NEAR(sh.T, bestT, 1e-9);
    }
  }
}

namespace {
// Distance from a segment to a triangle by another route: the distance from p(t) to the triangle
// is convex in t, so a golden-section search with the point query finds its minimum.
double GoldenSegmentTriangleDistance(const rp::Vec3& a, const rp::Vec3& b, const rp::Vec3& p, const rp::Vec3& q,
                                     const rp::Vec3& r) {
  auto f = [&](double t) {
    double bary[3];
    const rp::Vec3 x = a + (b - a) * t;
    return rp::Norm(rp::BVH::ClosestPointOnTriangle(x, p, q, r, bary) - x);
  };
  double lo = 0, hi = 1;
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 200; ++i) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (f(m1) < f(m2)) hi = m2;
    else lo = m1;
  }
  return std::min({f(0), f(1), f(0.5 * (lo + hi))});
}
}  // namespace

TEST(BVH, SegmentClosestMatchesAnIndependentSearchOverEveryTriangle) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-40, 40), s(0.5, 6);
  rp::TriangleMesh m;
  for (int i = 0; i < 600; ++i) {
    const rp::Vec3 c{u(rng), u(rng), u(rng)};
    const double size = s(rng);
    const int32_t base = static_cast<int32_t>(m.Points.size());
    for (int k = 0; k < 3; ++k) m.Points.push_back(c + rp::Vec3{u(rng), u(rng), u(rng)} * (size / 40));
    m.Triangles.push_back({base, base + 1, base + 2});
  }
  rp::BVH bvh;
  bvh.Build(m);
  uint32_t warm = 0;
  for (int q = 0; q < 150; ++q) {
    const rp::Vec3 a{u(rng), u(rng), u(rng)}, b = q % 3 == 0 ? a : rp::Vec3{u(rng), u(rng), u(rng)};  // points too
    double reference = HUGE_VAL;
    for (const auto& t : m.Triangles)
      reference = std::min(reference, GoldenSegmentTriangleDistance(a, b, m.Points[t[0]], m.Points[t[1]], m.Points[t[2]]));
    rp::SegmentClosestHit hit;
    ASSERT_TRUE(bvh.ClosestToSegment(a, b, HUGE_VAL, hit, q % 2 ? &warm : nullptr));
    EXPECT_NEAR(std::sqrt(hit.Distance2), reference, 1e-7) << "query " << q;
    EXPECT_NEAR(rp::Norm(hit.SegmentPoint - hit.SurfacePoint), std::sqrt(hit.Distance2), 1e-9);
    EXPECT_NEAR(rp::Norm(hit.SegmentPoint - (a + (b - a) * hit.T)), 0, 1e-9);
    warm = hit.Leaf;
    rp::SegmentClosestHit bounded;
    // Nothing within half the distance, unless the segment crosses the surface (the search's
    // reference is then 0 to rounding).
    EXPECT_EQ(bvh.ClosestToSegment(a, b, 0.5 * reference, bounded), reference < 1e-9) << "query " << q;
  }
}

TEST(BVH, SegmentClearanceFromASphereIsItsClosedForm) {
  // A segment at height h above the centre of a sphere of radius R misses it by h - R (up to the
  // icosphere's flats, at most R(1 - cos of half its edge angle)); one through it touches.
  const double R = 10;
  const rp::TriangleMesh m = rp::shapes::Sphere({0, 0, 0}, R, 5);
  rp::BVH bvh;
  bvh.Build(m);
  rp::SegmentClosestHit hit;
  for (double h : {10.5, 12.0, 20.0}) {
    ASSERT_TRUE(bvh.ClosestToSegment({-30, 0, h}, {30, 0, h}, HUGE_VAL, hit));
    EXPECT_NEAR(std::sqrt(hit.Distance2), h - R, 0.01);
    EXPECT_NEAR(hit.T, 0.5, 0.02);
  }
  ASSERT_TRUE(bvh.ClosestToSegment({-30, 1, 2}, {30, 1, 2}, HUGE_VAL, hit));
  EXPECT_EQ(hit.Distance2, 0);
  // Queries do not allocate.
  const uint64_t before = rp::alloc::ThreadAllocations();
  for (int i = 0; i < 200; ++i) bvh.ClosestToSegment({-30, 0, 11.0 + i}, {30, 5, 11.0}, HUGE_VAL, hit, &hit.Leaf);
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
}

// A display-sized mesh is built on several threads (rpBVH.cxx, BuildThreads): its tree must answer
// as the brute force does, with the degenerate triangles left out and every source index kept.
TEST(BVH, LargeMeshBuiltOnThreadsMatchesBruteForce) {
  rp::TriangleMesh m = rp::shapes::Sphere({3, -2, 1}, 40, 6);
  ASSERT_GT(m.Triangles.size(), 50000u);
  const size_t valid = m.Triangles.size();
  for (int i = 0; i < 100; ++i) m.Triangles.push_back({0, 0, 1});  // zero area: skipped
  rp::BVH bvh;
  bvh.Build(m);
  EXPECT_EQ(bvh.NumberOfTriangles(), valid);
  EXPECT_LE(bvh.NumberOfNodes(), 2 * valid);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-60, 60);
  for (int q = 0; q < 200; ++q) {
    const rp::Vec3 p{u(rng), u(rng), u(rng)};
    rp::ClosestPointHit hit;
    ASSERT_TRUE(bvh.ClosestPoint(p, HUGE_VAL, hit));
    const rp::ClosestPointHit brute = BruteClosest(m, p);
    EXPECT_NEAR(hit.Distance2, brute.Distance2, 1e-9 * (1 + brute.Distance2));
    ASSERT_LT(hit.Triangle, valid);
  }
}

// The triangle grid (the level-of-detail deviation check's structure for a large surface) gives
// the brute-force answer everywhere: on and near a sphere, inside it, far outside the grid's box
// (rings of empty cells), within a distance bound, on a soup of uneven and overlapping triangles.
TEST(TriangleGrid, ClosestPointMatchesBruteForceOnASphereAndFarAway) {
  const rp::TriangleMesh m = rp::shapes::Sphere({5, -3, 2}, 20, 4);
  rp::TriangleGrid grid;
  grid.Build(m);
  ASSERT_FALSE(grid.Empty());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> near(-25, 25), far(-400, 400);
  for (int i = 0; i < 600; ++i) {
    const bool isFar = i % 3 == 0;
    const rp::Vec3 p = rp::Vec3{5, -3, 2} + (isFar ? rp::Vec3{far(rng), far(rng), far(rng)}
                                                   : rp::Vec3{near(rng), near(rng), near(rng)});
    rp::ClosestPointHit hit;
    ASSERT_TRUE(grid.ClosestPoint(p, HUGE_VAL, hit));
    const rp::ClosestPointHit brute = BruteClosest(m, p);
    ASSERT_NEAR(hit.Distance2, brute.Distance2, 1e-9 * (1 + brute.Distance2)) << "query " << i;
    const auto& t = m.Triangles[hit.Triangle];
    const rp::Vec3 q = m.Points[t[0]] * hit.Barycentric[0] + m.Points[t[1]] * hit.Barycentric[1] +
                       m.Points[t[2]] * hit.Barycentric[2];
    EXPECT_NEAR(rp::Norm(q - hit.Point), 0.0, 1e-9);
    // Any triangle within a distance: just above and just below the exact one.
    const double d = std::sqrt(brute.Distance2);
    EXPECT_TRUE(grid.AnyWithin(p, d * (1 + 1e-9) + 1e-12)) << "query " << i;
    EXPECT_FALSE(grid.AnyWithin(p, d * (1 - 1e-6) - 1e-9)) << "query " << i;
  }
  rp::ClosestPointHit hit;
  EXPECT_FALSE(grid.ClosestPoint({5, -3, 2 + 40}, 5.0, hit));  // the surface is 20 mm away
  EXPECT_TRUE(grid.ClosestPoint({5, -3, 2 + 24}, 5.0, hit));
  EXPECT_NEAR(std::sqrt(hit.Distance2), 4.0, 0.05);
}

TEST(TriangleGrid, RandomSoupAndDegenerateTrianglesMatchBruteForce) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-50, 50), s(0.01, 30);
  rp::TriangleMesh m;
  for (int i = 0; i < 2000; ++i) {  // sizes from 0.01 to 30 mm: the cell size fits none of them
    const rp::Vec3 c{u(rng), u(rng), i % 7 == 0 ? 0.0 : u(rng)};
    const double size = s(rng);
    const int32_t base = static_cast<int32_t>(m.Points.size());
    for (int k = 0; k < 3; ++k) m.Points.push_back(c + rp::Vec3{u(rng), u(rng), u(rng)} * (size / 50));
    m.Triangles.push_back({base, base + 1, base + 2});
  }
  m.Triangles.push_back({0, 0, 1});  // zero area: skipped, never the answer
  rp::TriangleGrid grid;
  grid.Build(m);
  for (int q = 0; q < 400; ++q) {
    const rp::Vec3 p{u(rng) * 2, u(rng) * 2, u(rng) * 2};
    rp::ClosestPointHit hit;
    ASSERT_TRUE(grid.ClosestPoint(p, HUGE_VAL, hit));
    EXPECT_NEAR(hit.Distance2, BruteClosest(m, p).Distance2, 1e-9) << "query " << q;
    EXPECT_LT(hit.Triangle, m.Triangles.size() - 1);
  }
}

TEST(TriangleGrid, EmptyFlatAndAllocationFree) {
  rp::TriangleGrid grid;
  rp::TriangleMesh empty;
  grid.Build(empty);
  rp::ClosestPointHit hit;
  EXPECT_FALSE(grid.ClosestPoint({0, 0, 0}, HUGE_VAL, hit));
  rp::TriangleMesh line;  // only zero-area triangles
  line.Points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  line.Triangles = {{0, 1, 2}};
  grid.Build(line);
  EXPECT_TRUE(grid.Empty());
  EXPECT_FALSE(grid.ClosestPoint({0, 0, 0}, HUGE_VAL, hit));
  // A flat square (a grid one cell thick along z) queried from above and below.
  rp::TriangleMesh square;
  square.Points = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  square.Triangles = {{0, 1, 2}, {0, 2, 3}};
  grid.Build(square);
  ASSERT_TRUE(grid.ClosestPoint({3, 4, 7}, HUGE_VAL, hit));
  EXPECT_NEAR(hit.Distance2, 49.0, 1e-12);
  ASSERT_TRUE(grid.ClosestPoint({13, 14, -2}, HUGE_VAL, hit));
  EXPECT_NEAR(hit.Distance2, 9 + 16 + 4, 1e-12);
  const rp::TriangleMesh sphere = rp::shapes::Sphere({0, 0, 0}, 10, 5);
  grid.Build(sphere);
  const uint64_t before = rp::alloc::ThreadAllocations();
  int hits = 0;
  for (int i = 0; i < 1000; ++i) {
    const double a = 0.01 * i;
    hits += grid.ClosestPoint({15 * std::cos(a), 15 * std::sin(a), 0.01 * i - 5}, HUGE_VAL, hit);
  }
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
  EXPECT_EQ(hits, 1000);
}
