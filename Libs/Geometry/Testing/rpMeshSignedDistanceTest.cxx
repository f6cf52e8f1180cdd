// Signed distance to closed meshes against closed-form answers: a box (exact: the mesh is the
// solid), an icosphere (distance to the polyhedron, bounded by the sphere's), points on faces,
// edges and corners, and open or inconsistently oriented meshes refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rpMeshSignedDistance.h"

namespace {

// Exact signed distance to an axis-aligned box.
double BoxDistance(const rp::Vec3& p, const rp::Vec3& lo, const rp::Vec3& hi) {
  rp::Vec3 q;
  double inside = -HUGE_VAL;
  for (int a = 0; a < 3; ++a) {
    const double c = 0.5 * (lo[a] + hi[a]), h = 0.5 * (hi[a] - lo[a]);
    q[a] = std::abs(p[a] - c) - h;
    inside = std::max(inside, q[a]);
  }
  const rp::Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return rp::Norm(outside) + std::min(inside, 0.0);
}

}  // namespace

TEST(MeshSignedDistance, BoxIsExactEverywhere) {
  const rp::Vec3 lo{-10, -5, -2}, hi{10, 5, 2};
  rp::MeshSignedDistance sdf;
  std::string error;
  ASSERT_TRUE(sdf.Build(rp::shapes::Box(lo, hi), error)) << error;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-15, 15);
  for (int i = 0; i < 20000; ++i) {
    const rp::Vec3 p{u(rng), u(rng) * 0.7, u(rng) * 0.4};
    ASSERT_NEAR(sdf.SignedDistance(p), BoxDistance(p, lo, hi), 1e-9) << p.x << " " << p.y << " " << p.z;
  }
  // Closest features that are corners and edges (the sign needs the pseudonormals there).
  EXPECT_NEAR(sdf.SignedDistance({11, 6, 3}), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(sdf.SignedDistance({11, 6, 0}), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(sdf.SignedDistance({9.5, 4.5, 0}), -0.5, 1e-12);
  // Bounded queries: farther than the bound reports nothing.
  double d = 123;
  EXPECT_FALSE(sdf.SignedDistance({30, 0, 0}, 5.0, d));
  EXPECT_EQ(d, 123);
  EXPECT_TRUE(sdf.SignedDistance({12, 0, 0}, 5.0, d));
  EXPECT_NEAR(d, 2.0, 1e-12);
}

TEST(MeshSignedDistance, SphereSignMatchesTheSolidAndDistanceIsBounded) {
  const double r = 20;
  rp::MeshSignedDistance sdf;
  std::string error;
  ASSERT_TRUE(sdf.Build(rp::shapes::Sphere({1, 2, 3}, r, 4), error)) << error;
  // The icosphere's vertices lie on the sphere, its faces inside it by at most the sagitta.
  const double sagitta = 0.05;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-30, 30);
  for (int i = 0; i < 20000; ++i) {
    const rp::Vec3 p{1 + u(rng), 2 + u(rng), 3 + u(rng)};
    const double exact = rp::Norm(p - rp::Vec3{1, 2, 3}) - r;
    const double d = sdf.SignedDistance(p);
    ASSERT_LE(d, exact + sagitta + 1e-9);
    ASSERT_GE(d, exact - 1e-9);
    if (std::abs(exact) > sagitta) {
      ASSERT_EQ(d < 0, exact < 0);
    }
  }
}

TEST(MeshSignedDistance, OpenOrFlippedMeshesAreRefused) {
  rp::MeshSignedDistance sdf;
  std::string error;
  EXPECT_FALSE(sdf.Build(rp::shapes::Square(5, 0), error));
  EXPECT_NE(error.find("not closed"), std::string::npos) << error;
  rp::TriangleMesh flipped = rp::shapes::Box({0, 0, 0}, {1, 1, 1});
  std::swap(flipped.Triangles[0][1], flipped.Triangles[0][2]);
  EXPECT_FALSE(sdf.Build(flipped, error));
  EXPECT_NE(error.find("same direction"), std::string::npos) << error;
  EXPECT_FALSE(sdf.Build(rp::TriangleMesh{}, error));
}
