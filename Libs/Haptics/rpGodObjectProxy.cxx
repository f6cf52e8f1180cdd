#include "rpGodObjectProxy.h"

#include <cmath>

namespace rp {

namespace {
// Projection of p onto the plane lifted by the gap.
inline Vec3 OntoPlane(const Vec3& p, const ContactPlane& plane) noexcept {
  return p - plane.Normal * (Dot(p - plane.Point, plane.Normal) - GodObjectProxy::Gap);
}
inline bool Above(const Vec3& p, const ContactPlane& plane) noexcept {
  return Dot(p - plane.Point, plane.Normal) >= GodObjectProxy::Gap * 0.5;
}
}  // namespace

void GodObjectProxy::Reset(const Vec3& position) noexcept {
  this->Current = ProxyState{};
  this->Current.Proxy = position;
}

Vec3 GodObjectProxy::Solve(const HapticScene& scene, const Vec3& from, const Vec3& goal, ContactPlane planes[3],
                           int& n) const noexcept {
  n = 0;
  Vec3 p = from;
  Vec3 target = goal;
  for (int pass = 0; pass < 4; ++pass) {
    const Vec3 d = target - p;
    if (Norm2(d) < 1e-20) break;
    SegmentHit hit;
    if (!scene.Tree.FirstHit(p, target, BVH::Faces::FrontOnly, hit)) {
      p = target;  // free move
      break;
    }
    const Vec3 normal = scene.Mesh.FaceNormals[hit.Triangle];
    const double approach = -Dot(d, normal);  // distance to the plane closed per unit of T
    double back = approach > 0 ? hit.T - Gap / approach : 0.0;
    if (back < 0) back = 0;
    p = p + d * back;
    if (n == 3) break;  // a fourth plane: stay where the third left us
    planes[n++] = ContactPlane{normal, hit.Point, hit.Triangle};
    if (n == 1) {
      target = OntoPlane(goal, planes[0]);
    } else if (n == 2) {
      // The newest plane alone may be the only active constraint (sliding off the first).
      const Vec3 alone = OntoPlane(goal, planes[1]);
      const Vec3 edge = Cross(planes[0].Normal, planes[1].Normal);
      if (Above(alone, planes[0])) {
        planes[0] = planes[1];
        n = 1;
        target = alone;
      } else if (Norm2(edge) < 1e-12) {  // parallel planes: one constraint
        n = 1;
        target = alone;
      } else {
        const Vec3 dir = Normalized(edge);  // slide along the crease
        target = p + dir * Dot(goal - p, dir);
      }
    } else {  // three planes: a corner; the proxy stops here
      const Vec3 alone = OntoPlane(goal, planes[2]);
      if (Above(alone, planes[0]) && Above(alone, planes[1])) {
        planes[0] = planes[2];
        n = 1;
        target = alone;
      } else {
        break;
      }
    }
  }
  return p;
}

const ProxyState& GodObjectProxy::Update(const HapticScene& scene, const Vec3& hip, bool friction,
                                         bool forceShading) noexcept {
  ProxyState& s = this->Current;
  const Vec3 previous = s.Proxy;
  const bool wasInContact = s.InContact;
  int n = 0;
  ContactPlane planes[3];
  Vec3 proxy = this->Solve(scene, previous, hip, planes, n);
  s.Sticking = false;
  if (n == 0) {
    s.Sliding = false;
    s.Proxy = proxy;
    s.InContact = false;
    s.PlaneCount = 0;
    s.ForceNormal = Vec3{};
    return s;
  }
  Vec3 normal{};
  for (int i = 0; i < n; ++i) normal += planes[i].Normal;
  normal = Normalized(normal);
  const Material& material = scene.MaterialOf(planes[0].Triangle);

  if (friction && wasInContact && material.StaticFriction > 0) {
    // Friction cone around the contact normal: the proxy sticks while the HIP stays inside the
    // cone seen from the previous proxy (static cone when at rest, dynamic cone once sliding);
    // when sliding, it trails the frictionless position so the spring's tangential/normal
    // ratio equals the dynamic coefficient.
    const double depth = Dot(proxy - hip, normal);
    Vec3 lag = previous - proxy;
    lag -= normal * Dot(lag, normal);
    const double lagLength = Norm(lag);
    if (depth > 0) {
      const double cone = s.Sliding ? material.DynamicFriction : material.StaticFriction;
      if (lagLength <= cone * depth) {
        proxy = previous;
        s.Sticking = true;
      } else {
        s.Sliding = true;
        const Vec3 target = proxy + lag * (material.DynamicFriction * depth / lagLength);
        int m = 0;
        ContactPlane slidePlanes[3];
        proxy = this->Solve(scene, previous, target, slidePlanes, m);
      }
    }
  }

  if (s.Sticking || !friction) s.Sliding = false;
  s.Proxy = proxy;
  s.InContact = true;
  s.PlaneCount = n;
  for (int i = 0; i < n; ++i) s.Planes[i] = planes[i];
  s.Triangle = planes[0].Triangle;
  s.Label = scene.Mesh.Label(planes[0].Triangle);
  s.ForceNormal = normal;
  if (forceShading && n == 1 && !scene.Mesh.VertexNormals.empty()) {
    // Phong-like shading: interpolate the vertex normals at the proxy's foot on the triangle.
    const auto& t = scene.Mesh.Triangles[planes[0].Triangle];
    double bary[3];
    BVH::ClosestPointOnTriangle(proxy, scene.Mesh.Points[t[0]], scene.Mesh.Points[t[1]], scene.Mesh.Points[t[2]], bary);
    const Vec3 shaded = Normalized(scene.Mesh.VertexNormals[t[0]] * bary[0] + scene.Mesh.VertexNormals[t[1]] * bary[1] +
                                   scene.Mesh.VertexNormals[t[2]] * bary[2]);
    if (Dot(shaded, normal) > 0.2) s.ForceNormal = shaded;  // ignore wildly bent normals (bad meshes)
  }
  return s;
}

}  // namespace rp
