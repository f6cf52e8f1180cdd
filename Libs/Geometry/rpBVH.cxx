#include "rpBVH.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>
#include <utility>

#include "rpMortonCode.h"

namespace rp {

namespace {
inline double BoxDistance2(const Vec3& p, const Vec3& lo, const Vec3& hi) noexcept {
  double d2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double v = p[i];
    if (v < lo[i]) d2 += (lo[i] - v) * (lo[i] - v);
    else if (v > hi[i]) d2 += (v - hi[i]) * (v - hi[i]);
  }
  return d2;
}

// Slab test: does the segment origin + t*dir, t in [0, tMax], touch the box?
inline bool SegmentTouchesBox(const Vec3& origin, const Vec3& invDir, double tMax, const Vec3& lo,
                              const Vec3& hi) noexcept {
  double t0 = 0, t1 = tMax;
  for (int i = 0; i < 3; ++i) {
    double tNear = (lo[i] - origin[i]) * invDir[i];
    double tFar = (hi[i] - origin[i]) * invDir[i];
    if (std::isnan(tNear) || std::isnan(tFar)) {  // 0 * inf: origin on the slab and parallel
      if (origin[i] < lo[i] || origin[i] > hi[i]) return false;
      continue;
    }
    if (tNear > tFar) std::swap(tNear, tFar);
    t0 = tNear > t0 ? tNear : t0;
    t1 = tFar < t1 ? tFar : t1;
    if (t0 > t1) return false;
  }
  return true;
}
}  // namespace

Vec3 BVH::ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                 double bary[3]) noexcept {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) { bary[0] = 1; bary[1] = 0; bary[2] = 0; return a; }
  const Vec3 bp = p - b;
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) { bary[0] = 0; bary[1] = 1; bary[2] = 0; return b; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    bary[0] = 1 - v; bary[1] = v; bary[2] = 0;
    return a + ab * v;
  }
  const Vec3 cp = p - c;
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) { bary[0] = 0; bary[1] = 0; bary[2] = 1; return c; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    bary[0] = 1 - w; bary[1] = 0; bary[2] = w;
    return a + ac * w;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    bary[0] = 0; bary[1] = 1 - w; bary[2] = w;
    return b + (c - b) * w;
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  bary[0] = 1 - v - w; bary[1] = v; bary[2] = w;
  return a + ab * v + ac * w;
}

namespace {
// Sorts (code, index) pairs by code, keeping the order of equal codes: least significant digit
// first, 11 bits a pass, skipping digits every key shares. Several times faster than std::sort
// for the hundreds of thousands of triangles of a display mesh; the same order (the input comes
// in index order), so the same tree.
void RadixSortByCode(std::vector<std::pair<uint64_t, uint32_t>>& keys) {
  constexpr int Bits = 11;
  constexpr size_t Buckets = size_t(1) << Bits;
  std::vector<std::pair<uint64_t, uint32_t>> other(keys.size());
  std::vector<size_t> count(Buckets);
  for (int shift = 0; shift < 64; shift += Bits) {
    std::fill(count.begin(), count.end(), 0);
    for (const auto& k : keys) ++count[(k.first >> shift) & (Buckets - 1)];
    if (std::any_of(count.begin(), count.end(), [&](size_t c) { return c == keys.size(); })) continue;
    size_t sum = 0;
    for (size_t& c : count) sum += std::exchange(c, sum);
    for (const auto& k : keys) other[count[(k.first >> shift) & (Buckets - 1)]++] = k;
    keys.swap(other);
  }
}

}  // namespace

namespace {
// Threads for building over `triangles`: one below a size where starting threads costs more than
// it saves (the haptic models of a scene), else the machine's (at most 8).
int BuildThreads(size_t triangles) {
  if (triangles < 50000) return 1;
  return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
}

// body(chunk, begin, end) over [0, n) in `chunks` contiguous chunks, one thread each (the caller
// runs the last).
template <class Body>
void ForChunks(size_t n, int chunks, const Body& body) {
  const size_t size = (n + static_cast<size_t>(chunks) - 1) / static_cast<size_t>(chunks);
  std::vector<std::thread> threads;
  for (int c = 0; c + 1 < chunks; ++c)
    threads.emplace_back([&, c] { body(c, std::min(n, c * size), std::min(n, (c + 1) * size)); });
  body(chunks - 1, std::min(n, (chunks - 1) * size), n);
  for (auto& thread : threads) thread.join();
}
}  // namespace

void BVH::Build(const TriangleMesh& mesh, int leafSize) {
  this->Nodes.clear();
  this->Tris.clear();
  this->Balls.clear();
  auto corners = [&](uint32_t i, Vec3& a, Vec3& b, Vec3& c) {
    const auto& t = mesh.Triangles[i];
    a = mesh.Points[static_cast<size_t>(t[0])], b = mesh.Points[static_cast<size_t>(t[1])],
    c = mesh.Points[static_cast<size_t>(t[2])];
  };
  // Every pass below but the sort runs in contiguous chunks on threads for a large mesh; the tree
  // is the same for any number of threads (the keys stay in triangle order before the stable sort).
  const int chunks = BuildThreads(mesh.Triangles.size());
  // The triangles with an area, and the box of their centroids; no copy of the corners yet.
  std::vector<std::vector<uint32_t>> kept(static_cast<size_t>(chunks));
  std::vector<Vec3> los(static_cast<size_t>(chunks), Vec3{HUGE_VAL, HUGE_VAL, HUGE_VAL});
  std::vector<Vec3> his(static_cast<size_t>(chunks), Vec3{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL});
  ForChunks(mesh.Triangles.size(), chunks, [&](int chunk, size_t begin, size_t end) {
    auto& mine = kept[static_cast<size_t>(chunk)];
    Vec3& lo = los[static_cast<size_t>(chunk)];
    Vec3& hi = his[static_cast<size_t>(chunk)];
    mine.reserve(end - begin);
    for (size_t i = begin; i < end; ++i) {
      Vec3 a, b, c;
      corners(static_cast<uint32_t>(i), a, b, c);
      if (Norm2(Cross(b - a, c - a)) == 0) continue;
      const Vec3 centroid = (a + b + c) / 3.0;
      lo = Min(lo, centroid);
      hi = Max(hi, centroid);
      mine.push_back(static_cast<uint32_t>(i));
    }
  });
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  std::vector<std::pair<uint64_t, uint32_t>> keys;
  {
    size_t total = 0;
    for (const auto& mine : kept) total += mine.size();
    keys.reserve(total);
  }
  for (int c = 0; c < chunks; ++c) {
    lo = Min(lo, los[static_cast<size_t>(c)]);
    hi = Max(hi, his[static_cast<size_t>(c)]);
    for (uint32_t i : kept[static_cast<size_t>(c)]) keys.push_back({0, i});
  }
  kept.clear();
  if (keys.empty()) return;
  // Sort along the Z-order curve of the centroids.
  const Vec3 extent = hi - lo;
  const double cells = static_cast<double>((1u << 21) - 1);
  const Vec3 scale{extent.x > 0 ? cells / extent.x : 0, extent.y > 0 ? cells / extent.y : 0,
                   extent.z > 0 ? cells / extent.z : 0};
  ForChunks(keys.size(), chunks, [&](int, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      auto& key = keys[k];
      Vec3 a, b, c;
      corners(key.second, a, b, c);
      const Vec3 centroid = (a + b + c) / 3.0 - lo;
      key.first = SpreadMortonBits(static_cast<uint64_t>(centroid.x * scale.x)) |
                  SpreadMortonBits(static_cast<uint64_t>(centroid.y * scale.y)) << 1 |
                  SpreadMortonBits(static_cast<uint64_t>(centroid.z * scale.z)) << 2;
    }
  });
  RadixSortByCode(keys);
  this->Tris.resize(keys.size());
  this->Balls.resize(keys.size());
  std::vector<uint64_t> codes(keys.size());
  ForChunks(keys.size(), chunks, [&](int, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      Tri& tri = this->Tris[k];
      corners(keys[k].second, tri.A, tri.B, tri.C);
      tri.Normal = Cross(tri.B - tri.A, tri.C - tri.A);
      tri.Source = keys[k].second;
      const Vec3 centroid = (tri.A + tri.B + tri.C) / 3.0;
      this->Balls[k] = {centroid, std::sqrt(std::max({Norm2(tri.A - centroid), Norm2(tri.B - centroid), Norm2(tri.C - centroid)}))};
      codes[k] = keys[k].first;
    }
  });
  keys = {};
  leafSize = std::max(1, leafSize);
  this->Nodes.reserve(2 * this->Tris.size() + 1);
  BuildSubtree(this->Nodes, this->Tris, codes, 0, static_cast<uint32_t>(this->Tris.size()), 0, leafSize, chunks);
}

uint32_t BVH::SplitOf(const std::vector<uint64_t>& codes, uint32_t begin, uint32_t end, int depth) {
  // Where the highest bit that differs between the first and last code flips; equal codes (or a
  // deep tree, to respect the traversal stack) split in the middle.
  uint32_t mid = begin + (end - begin) / 2;
  const uint64_t first = codes[begin], last = codes[end - 1];
  if (first != last && depth < MaxDepth / 2) {
    const int bit = 63 - __builtin_clzll(first ^ last);
    const uint64_t mask = ~0ULL << bit;  // codes with this prefix bit set go right
    const uint64_t pivot = (first & mask) | (1ULL << bit);
    mid = static_cast<uint32_t>(std::lower_bound(codes.begin() + begin, codes.begin() + end, pivot) - codes.begin());
  }
  return mid;
}

uint32_t BVH::BuildSubtree(std::vector<Node>& nodes, const std::vector<Tri>& tris, const std::vector<uint64_t>& codes,
                           uint32_t begin, uint32_t end, int depth, int leafSize, int threads) {
  const uint32_t count = end - begin;
  if (threads <= 1 || count <= 4096u || depth >= MaxDepth / 2)
    return BuildRange(nodes, tris, codes, begin, end, depth, leafSize);
  // The left half on this thread into `nodes`, the right half on another into its own array,
  // appended after the left one (its right-child indices shifted): the serial build's layout.
  const uint32_t index = static_cast<uint32_t>(nodes.size());
  nodes.emplace_back();
  const uint32_t mid = SplitOf(codes, begin, end, depth);
  std::vector<Node> rightNodes;
  rightNodes.reserve(2 * (end - mid) + 1);
  std::thread rightThread([&] { BuildSubtree(rightNodes, tris, codes, mid, end, depth + 1, leafSize, threads / 2); });
  const uint32_t left = BuildSubtree(nodes, tris, codes, begin, mid, depth + 1, leafSize, threads - threads / 2);
  rightThread.join();
  const uint32_t right = static_cast<uint32_t>(nodes.size());
  for (Node& node : rightNodes)
    if (node.Count == 0) node.First += right;
  nodes.insert(nodes.end(), rightNodes.begin(), rightNodes.end());
  nodes[index].Lo = Min(nodes[left].Lo, nodes[right].Lo);
  nodes[index].Hi = Max(nodes[left].Hi, nodes[right].Hi);
  nodes[index].First = right;
  nodes[index].Count = 0;
  return index;
}

uint32_t BVH::BuildRange(std::vector<Node>& nodes, const std::vector<Tri>& tris, const std::vector<uint64_t>& codes,
                         uint32_t begin, uint32_t end, int depth, int leafSize) {
  const uint32_t index = static_cast<uint32_t>(nodes.size());
  nodes.emplace_back();
  const uint32_t count = end - begin;
  if (count <= static_cast<uint32_t>(leafSize) || depth >= MaxDepth - 2) {  // the stack bounds the depth
    Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (uint32_t i = begin; i < end; ++i) {
      const Tri& t = tris[i];
      lo = Min(lo, Min(t.A, Min(t.B, t.C)));
      hi = Max(hi, Max(t.A, Max(t.B, t.C)));
    }
    nodes[index].Lo = lo;
    nodes[index].Hi = hi;
    nodes[index].First = begin;
    nodes[index].Count = count;
    return index;
  }
  const uint32_t mid = SplitOf(codes, begin, end, depth);
  const uint32_t left = BuildRange(nodes, tris, codes, begin, mid, depth + 1, leafSize);
  const uint32_t right = BuildRange(nodes, tris, codes, mid, end, depth + 1, leafSize);
  nodes[index].Lo = Min(nodes[left].Lo, nodes[right].Lo);
  nodes[index].Hi = Max(nodes[left].Hi, nodes[right].Hi);
  nodes[index].First = right;
  nodes[index].Count = 0;
  return index;
}

bool BVH::ClosestPoint(const Vec3& p, double maxDistance, ClosestPointHit& hit) const noexcept {
  if (this->Nodes.empty()) return false;
  double best2 = std::isfinite(maxDistance) ? maxDistance * maxDistance : std::numeric_limits<double>::infinity();
  bool found = false;
  uint32_t stack[MaxDepth];
  int top = 0;
  if (BoxDistance2(p, this->Nodes[0].Lo, this->Nodes[0].Hi) > best2) return false;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = this->Nodes[stack[--top]];
    if (BoxDistance2(p, node.Lo, node.Hi) > best2) continue;
    if (node.Count > 0) {
      for (uint32_t i = node.First; i < node.First + node.Count; ++i) {
        const Tri& t = this->Tris[i];
        double bary[3];
        const Vec3 q = ClosestPointOnTriangle(p, t.A, t.B, t.C, bary);
        const double d2 = Norm2(q - p);
        if (d2 <= best2) {
          best2 = d2;
          found = true;
          hit.Point = q;
          hit.Distance2 = d2;
          hit.Triangle = t.Source;
          hit.Barycentric[0] = bary[0]; hit.Barycentric[1] = bary[1]; hit.Barycentric[2] = bary[2];
        }
      }
      continue;
    }
    // Visit the nearer child first: push it last.
    const uint32_t left = static_cast<uint32_t>(&node - this->Nodes.data()) + 1, right = node.First;
    const double dl = BoxDistance2(p, this->Nodes[left].Lo, this->Nodes[left].Hi);
    const double dr = BoxDistance2(p, this->Nodes[right].Lo, this->Nodes[right].Hi);
    if (dl <= dr) {
      if (dr <= best2) stack[top++] = right;
      if (dl <= best2) stack[top++] = left;
    } else {
      if (dl <= best2) stack[top++] = left;
      if (dr <= best2) stack[top++] = right;
    }
  }
  return found;
}

bool BVH::FirstHit(const Vec3& a, const Vec3& b, Faces faces, SegmentHit& hit) const noexcept {
  if (this->Nodes.empty()) return false;
  const Vec3 dir = b - a;
  if (Norm2(dir) == 0) return false;
  const Vec3 invDir{1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z};
  double bestT = 1.0;
  bool found = false;
  uint32_t stack[MaxDepth];
  int top = 0;
  stack[top++] = 0;
  // Barycentric tolerance: a segment through a shared edge must not slip between two triangles.
  constexpr double edgeTolerance = 1e-9;
  while (top > 0) {
    const uint32_t nodeIndex = stack[--top];
    const Node& node = this->Nodes[nodeIndex];
    if (!SegmentTouchesBox(a, invDir, bestT, node.Lo, node.Hi)) continue;
    if (node.Count > 0) {
      for (uint32_t i = node.First; i < node.First + node.Count; ++i) {
        const Tri& t = this->Tris[i];
        const double approach = Dot(dir, t.Normal);
        if (faces == Faces::FrontOnly && approach >= 0) continue;
        // Möller–Trumbore.
        const Vec3 e1 = t.B - t.A, e2 = t.C - t.A;
        const Vec3 pv = Cross(dir, e2);
        const double det = Dot(e1, pv);
        if (det == 0) continue;
        const double inv = 1.0 / det;
        const Vec3 tv = a - t.A;
        const double u = Dot(tv, pv) * inv;
        if (u < -edgeTolerance || u > 1 + edgeTolerance) continue;
        const Vec3 qv = Cross(tv, e1);
        const double v = Dot(dir, qv) * inv;
        if (v < -edgeTolerance || u + v > 1 + edgeTolerance) continue;
        const double s = Dot(e2, qv) * inv;
        if (s < 0 || s > bestT) continue;
        bestT = s;
        found = true;
        hit.T = s;
        hit.Point = a + dir * s;
        hit.Triangle = t.Source;
        hit.Barycentric[0] = 1 - u - v; hit.Barycentric[1] = u; hit.Barycentric[2] = v;
      }
      continue;
    }
    stack[top++] = node.First;
    stack[top++] = nodeIndex + 1;
  }
  return found;
}

namespace {

// Closest points of segments p1→q1 and p2→q2 (Ericson, RTCD 5.1.9): parameters s, t in [0,1].
double SegmentSegmentDistance2(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, double& s, double& t,
                               Vec3& c1, Vec3& c2) noexcept {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = Dot(d1, d1), e = Dot(d2, d2), f = Dot(d2, r);
  constexpr double eps = 1e-300;
  if (a <= eps && e <= eps) {
    s = t = 0;
    c1 = p1, c2 = p2;
    return Norm2(c1 - c2);
  }
  if (a <= eps) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = Dot(d1, r);
    if (e <= eps) {
      t = 0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = Dot(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
  return Norm2(c1 - c2);
}

// Where the segment p0→p1 crosses the triangle's plane inside the triangle: fraction t, or -1.
double SegmentCrossesTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) noexcept {
  const Vec3 dir = p1 - p0, e1 = b - a, e2 = c - a;
  const Vec3 pv = Cross(dir, e2);
  const double det = Dot(e1, pv);
  if (det == 0) return -1;
  const double inv = 1.0 / det;
  const Vec3 tv = p0 - a;
  const double u = Dot(tv, pv) * inv;
  if (u < 0 || u > 1) return -1;
  const Vec3 qv = Cross(tv, e1);
  const double v = Dot(dir, qv) * inv;
  if (v < 0 || u + v > 1) return -1;
  const double t = Dot(e2, qv) * inv;
  return t >= 0 && t <= 1 ? t : -1;
}

// A lower bound of the squared distance between the segment a + t d (t in [0,1]) and a box, from
// separating axes, without the exact (piecewise quadratic) distance: the gap between the box and
// the segment's own box, and the gap in the plane of the segment's direction u and the direction
// n across it towards the box's centre. In that plane the segment is a piece of the u axis and the
// box lies inside the rectangle of its projections (centre ± the half-sizes' extents on n and on
// u), so the distance is at least the 2D distance between the two. Tight for the long segments
// the queries pass beside small boxes with; the triangles decide the answer exactly.
inline double SegmentBoxLowerBound2(const Vec3& a, const Vec3& u, double length, const Vec3& segLo, const Vec3& segHi,
                                    const Vec3& lo, const Vec3& hi) noexcept {
  double gap2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double g = std::max(lo[i] - segHi[i], segLo[i] - hi[i]);
    if (g > 0) gap2 += g * g;
  }
  const Vec3 half = (hi - lo) * 0.5, toCenter = (lo + hi) * 0.5 - a;
  const double along = Dot(toCenter, u);
  const double extentU = std::fabs(u.x) * half.x + std::fabs(u.y) * half.y + std::fabs(u.z) * half.z;
  const double gapU = std::max(along - extentU - length, -(along + extentU));
  const Vec3 across = toCenter - u * along;
  const double acrossLength = Norm(across);
  double gapN = 0;
  if (acrossLength > 0) {
    const Vec3 n = across / acrossLength;
    gapN = acrossLength - (std::fabs(n.x) * half.x + std::fabs(n.y) * half.y + std::fabs(n.z) * half.z);
  }
  const double plane2 = (gapU > 0 ? gapU * gapU : 0.0) + (gapN > 0 ? gapN * gapN : 0.0);
  return std::max(gap2, plane2);
}

}  // namespace

double BVH::SegmentTriangleDistance2(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c,
                                     Vec3& onSegment, Vec3& onTriangle, double& t) noexcept {
  const double cross = SegmentCrossesTriangle(p0, p1, a, b, c);
  if (cross >= 0) {
    t = cross;
    onSegment = onTriangle = p0 + (p1 - p0) * cross;
    return 0;
  }
  // Not crossing: the closest pair has an end of the segment or a point of an edge.
  double bary[3], best;
  onTriangle = ClosestPointOnTriangle(p0, a, b, c, bary);
  onSegment = p0;
  t = 0;
  best = Norm2(onTriangle - p0);
  const Vec3 q1 = ClosestPointOnTriangle(p1, a, b, c, bary);
  if (const double d2 = Norm2(q1 - p1); d2 < best) best = d2, onSegment = p1, onTriangle = q1, t = 1;
  const Vec3* corners[3] = {&a, &b, &c};
  for (int e = 0; e < 3; ++e) {
    double s, u;
    Vec3 c1, c2;
    const double d2 = SegmentSegmentDistance2(p0, p1, *corners[e], *corners[(e + 1) % 3], s, u, c1, c2);
    if (d2 < best) best = d2, onSegment = c1, onTriangle = c2, t = s;
  }
  return best;
}

bool BVH::ClosestToSegment(const Vec3& a, const Vec3& b, double maxDistance, SegmentClosestHit& hit,
                           const uint32_t* warmLeaf) const noexcept {
  if (this->Nodes.empty()) return false;
  double best2 = std::isfinite(maxDistance) ? maxDistance * maxDistance : std::numeric_limits<double>::infinity();
  bool found = false;
  const Vec3 d = b - a, segLo = Min(a, b), segHi = Max(a, b);
  const double length2 = Norm2(d), invLength2 = length2 > 0 ? 1.0 / length2 : 0.0;
  auto test = [&](uint32_t i) {
    // Two cheap lower bounds first. The triangle's ball: farther than the best by its radius, the
    // triangle is too.
    const Ball& ball = this->Balls[i];
    const Vec3 toCenter = ball.Center - a;
    const double along = Dot(toCenter, d) * invLength2;
    const Vec3 across = toCenter - d * along;  // the centroid seen down the segment's line
    const double fromCenter = Norm(ball.Center - (a + d * std::clamp(along, 0.0, 1.0))) - ball.Radius;
    if (fromCenter > 0 && fromCenter * fromCenter > best2) return;
    // Down the line: the triangle is convex, so no point of it is nearer the line than its
    // corners' least extent towards the line (a triangle facing the segment, as the ones nearest
    // it on a smooth surface do, has almost none): a bound on the distance to the segment too.
    const Tri& tri = this->Tris[i];
    const double acrossLength = Norm(across);
    if (acrossLength > 0) {
      const Vec3 w = across / acrossLength;
      double nearest = acrossLength;
      for (const Vec3* corner : {&tri.A, &tri.B, &tri.C}) {
        const Vec3 c = *corner - a;
        nearest = std::min(nearest, Dot(c - d * (Dot(c, d) * invLength2), w));
      }
      if (nearest > 0 && nearest * nearest > best2) return;
    }
    Vec3 onSegment, onTriangle;
    double t;
    const double d2 = SegmentTriangleDistance2(a, b, tri.A, tri.B, tri.C, onSegment, onTriangle, t);
    if (d2 > best2 || (found && d2 == best2)) return;
    best2 = d2;
    found = true;
    hit.SegmentPoint = onSegment, hit.SurfacePoint = onTriangle, hit.Distance2 = d2, hit.T = t;
    hit.Triangle = tri.Source, hit.Leaf = i;
  };
  if (warmLeaf && *warmLeaf < this->Tris.size()) test(*warmLeaf);
  const double length = std::sqrt(length2);
  const Vec3 u = length > 0 ? d / length : Vec3{1, 0, 0};
  auto bound = [&](const Node& node) { return SegmentBoxLowerBound2(a, u, length, segLo, segHi, node.Lo, node.Hi); };
  // The stack keeps each node's bound, computed once (the exact box distance is not free).
  std::pair<uint32_t, double> stack[MaxDepth];
  int top = 0;
  const double rootBound = bound(this->Nodes[0]);
  if (rootBound > best2) return found;
  stack[top++] = {0, rootBound};
  while (top > 0 && !(found && best2 == 0)) {  // a crossing cannot be beaten
    const auto [index, nodeBound] = stack[--top];
    if (nodeBound > best2) continue;
    const Node& node = this->Nodes[index];
    if (node.Count > 0) {
      for (uint32_t i = node.First; i < node.First + node.Count; ++i) test(i);
      continue;
    }
    const uint32_t left = index + 1, right = node.First;
    const double dl = bound(this->Nodes[left]), dr = bound(this->Nodes[right]);
    if (dl <= dr) {  // the nearer child last, so it is visited first
      if (dr <= best2) stack[top++] = {right, dr};
      if (dl <= best2) stack[top++] = {left, dl};
    } else {
      if (dl <= best2) stack[top++] = {left, dl};
      if (dr <= best2) stack[top++] = {right, dr};
    }
  }
  return found;
}

}  // namespace rp
