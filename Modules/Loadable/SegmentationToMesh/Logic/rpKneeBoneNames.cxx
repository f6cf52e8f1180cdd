#include "rpKneeBoneNames.h"

#include "rpKneePhantom.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "rpLabelTable.h"

namespace rp {

namespace {

// RAS axes of BoundsRAS / CentroidRAS.
constexpr int R = 0, A = 1, S = 2;

double Extent(const BoneInfo& b, int axis) { return b.BoundsRAS[2 * axis + 1] - b.BoundsRAS[2 * axis]; }

// Overlap of two bones' ranges along an axis (mm, < 0 when apart).
double Overlap(const BoneInfo& a, const BoneInfo& b, int axis) {
  return std::min(a.BoundsRAS[2 * axis + 1], b.BoundsRAS[2 * axis + 1]) -
         std::max(a.BoundsRAS[2 * axis], b.BoundsRAS[2 * axis]);
}

bool Named(const BoneInfo& b) { return !b.Name.empty(); }

void Name(BoneInfo& b, const std::string& name) {
  b.Name = name;
  b.NamedBy = "knee anatomy";
}

// The bones of one leg (indices into `bones`).
void NameLeg(std::vector<BoneInfo>& bones, const std::vector<size_t>& leg, const std::string& suffix) {
  auto find = [&](const std::string& name) -> BoneInfo* {
    for (size_t i : leg)
      if (bones[i].Name == name + suffix || bones[i].Name == name) return &bones[i];
    return nullptr;
  };
  // Tibia: the largest bone with a fibula beside it, a slender bone much smaller than it that
  // runs along it (most of its height within the tibia's) behind it. Seeds may have named either.
  BoneInfo* tibia = find("tibia");
  BoneInfo* fibula = find("fibula");
  if (!tibia) {
    for (size_t t : leg) {  // largest first
      BoneInfo& candidate = bones[t];
      if (Named(candidate) || candidate.VolumeMl < 20) continue;
      BoneInfo* partner = fibula;
      if (!partner) {
        for (size_t f : leg) {
          BoneInfo& other = bones[f];
          if (f == t || Named(other)) continue;
          const bool smaller = other.VolumeMl < 0.4 * candidate.VolumeMl && other.VolumeMl > 0.01 * candidate.VolumeMl;
          const bool alongside = Overlap(other, candidate, S) > 0.5 * Extent(other, S);
          const bool slender = Extent(other, S) > 1.5 * std::max(Extent(other, R), Extent(other, A));
          const bool behind = other.CentroidRAS[A] < candidate.CentroidRAS[A] - 5;
          const double dr = other.CentroidRAS[R] - candidate.CentroidRAS[R], da = other.CentroidRAS[A] - candidate.CentroidRAS[A];
          if (smaller && alongside && slender && behind && std::hypot(dr, da) < 80) {
            partner = &other;
            break;  // largest first
          }
        }
      }
      if (partner) {
        tibia = &candidate;
        if (!fibula) fibula = partner;
        break;
      }
    }
  }
  // Without a fibula: two large bones one above the other are femur (upper) and tibia (lower).
  BoneInfo* femurMain = find("femur");
  if (!tibia) {
    std::vector<size_t> large;
    for (size_t i : leg)
      if (!Named(bones[i]) && bones[i].VolumeMl >= 20) large.push_back(i);
    for (size_t x = 0; x < large.size() && !tibia; ++x)
      for (size_t y = 0; y < large.size() && !tibia; ++y) {
        BoneInfo& upper = bones[large[x]];
        BoneInfo& lower = bones[large[y]];
        if (x == y || upper.CentroidRAS[S] <= lower.CentroidRAS[S] + 30) continue;
        if (Overlap(upper, lower, R) <= 0 || Overlap(upper, lower, A) <= 0) continue;
        if (Overlap(upper, lower, S) > 0.3 * std::min(Extent(upper, S), Extent(lower, S))) continue;
        tibia = &lower;
        if (!femurMain) femurMain = &upper;
      }
  }
  if (!tibia) return;  // not a recognisable knee: leave the names to "Bone N"
  if (!Named(*tibia)) Name(*tibia, "tibia" + suffix);
  if (fibula && !Named(*fibula)) Name(*fibula, "fibula" + suffix);
  if (femurMain && !Named(*femurMain)) Name(*femurMain, "femur" + suffix);
  // Femur: pieces above the tibial plateau over the tibia's footprint (condyles cut by the field
  // of view come as several pieces: they are one bone).
  const double plateau = tibia->BoundsRAS[2 * S + 1];
  for (size_t i : leg) {
    BoneInfo& b = bones[i];
    if (Named(b) || b.VolumeMl < 0.5) continue;
    const bool above = b.CentroidRAS[S] > plateau - 15 && b.BoundsRAS[2 * S] > tibia->CentroidRAS[S];
    const bool over = Overlap(b, *tibia, R) > -10 && b.CentroidRAS[A] < tibia->BoundsRAS[2 * A + 1] + 5 &&
                      b.CentroidRAS[A] > tibia->BoundsRAS[2 * A] - 10;
    if (above && over && (b.VolumeMl >= 2 || femurMain)) Name(b, "femur" + suffix);
  }
  // Patella: small, in front of the femur and tibia, at the joint.
  double front = tibia->BoundsRAS[2 * A + 1];
  for (size_t i : leg)
    if (bones[i].Name == "femur" + suffix) front = std::max(front, bones[i].BoundsRAS[2 * A + 1] - 10);
  BoneInfo* patella = find("patella");
  for (size_t i : leg) {
    BoneInfo& b = bones[i];
    if (patella || Named(b) || b.VolumeMl > 60) continue;
    const bool anterior = b.CentroidRAS[A] > front - 5;
    const bool atJoint = b.CentroidRAS[S] > plateau - 30 && b.CentroidRAS[S] < plateau + 100;
    const bool inLine = Overlap(b, *tibia, R) > -15;
    if (anterior && atJoint && inLine) {
      Name(b, "patella" + suffix);
      patella = &b;
    }
  }
}

}  // namespace

void NameKneeBones(std::vector<BoneInfo>& bones, const double ctBounds[6]) {
  (void)ctBounds;
  if (bones.empty()) return;
  // Legs: bones fall into groups along R with a gap of more than 20 mm between them.
  std::vector<size_t> order(bones.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return bones[a].BoundsRAS[2 * R] < bones[b].BoundsRAS[2 * R]; });
  std::vector<std::vector<size_t>> legs(1);
  double reach = bones[order[0]].BoundsRAS[2 * R + 1];
  for (size_t n = 0; n < order.size(); ++n) {
    const BoneInfo& b = bones[order[n]];
    if (n > 0 && b.BoundsRAS[2 * R] > reach + 20 && bones[order[n]].VolumeMl >= 5) legs.emplace_back();
    legs.back().push_back(order[n]);
    reach = std::max(reach, b.BoundsRAS[2 * R + 1]);
  }
  // Largest bone first within a leg (the order the rules expect).
  for (auto& leg : legs)
    std::sort(leg.begin(), leg.end(), [&](size_t a, size_t b) { return bones[a].VolumeMl > bones[b].VolumeMl; });
  if (legs.size() == 2) {
    // +R is the patient's right: the leg further along R is the right one.
    NameLeg(bones, legs[0], " left");
    NameLeg(bones, legs[1], " right");
  } else {
    for (const auto& leg : legs) NameLeg(bones, leg, "");
  }
}

bool KneeBoneColor(const std::string& name, std::array<double, 3>& color) {
  // The knee bones' colours are the phantom's (rp::KneeBones(), one table for the demo, its
  // pictures and `roboplan mesh`): "tibia left" is a tibia.
  std::string base = name.substr(0, name.find(' '));
  std::transform(base.begin(), base.end(), base.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const KneeBone& bone : KneeBones())
    if (base == bone.ID) {
      color = bone.Color;
      return true;
    }
  return false;
}

std::array<double, 3> BoneColor(const std::string& name, int labelValue) {
  std::array<double, 3> color;
  return KneeBoneColor(name, color) ? color : DefaultLabelColor(labelValue);
}

}  // namespace rp
