#pragma once
// The virtual fixtures the servo renders, as one immutable snapshot (as the haptic scene): each
// fixture's geometry (shared between snapshots: switching one on or retuning it builds a new
// snapshot without rebuilding a BVH), its tuning and whether it is on. Built on the main thread
// (from the plan's nodes) and handed to a servo inside a FixtureConstraint (rpFixtureConstraint.h),
// through the servo's ConstraintExchange, without locks.
#include <memory>
#include <string>
#include <vector>

#include "rpHapticDevice.h"
#include "rpVirtualFixture.h"

namespace rp {

/// At most this many fixtures in a set (the servo keeps their memory in fixed arrays).
constexpr int MaxFixtures = 16;

struct FixtureEntry {
  std::shared_ptr<const VirtualFixture> Fixture;
  FixtureTuning Tuning;
  bool Enabled = true;  // a switched-off fixture stays in the set so its force fades out
};

struct FixtureSet {
  std::vector<FixtureEntry> Entries;
  uint64_t Version = 0;

  /// Adds a fixture; false with `error` naming it when the set is full, its id repeats or its
  /// tuning is not usable (FixtureTuningProblem).
  bool Add(std::shared_ptr<const VirtualFixture> fixture, const FixtureTuning& tuning, bool enabled, std::string& error);
  int Count() const { return static_cast<int>(this->Entries.size()); }
  /// nullptr when there is none with this id.
  const FixtureEntry* Find(uint32_t id) const;
  /// A new snapshot sharing the geometry, with every fixture of `kind` switched on or off.
  std::unique_ptr<FixtureSet> WithKindEnabled(FixtureKind kind, bool enabled) const;
};

/// How each fixture feels unless tuned (for the seed paper's Phantom Omni, 0.7 N/mm and 3.3 N;
/// the Haptics README says how to tune them).
FixtureTuning DefaultFixtureTuning(FixtureKind kind);

/// "" when the tuning can be used; else what is wrong with it (negative stiffness, a release
/// nearer than the capture, ...).
std::string FixtureTuningProblem(const FixtureTuning& tuning);
/// The stiffness a device renders of a fixture alone (its nominal maximum and Colgate–Schenkel's
/// passive limit at `period` with the fixture's damping), as the servo renders it.
double RenderedFixtureStiffness(const FixtureTuning& tuning, const DeviceInfo& device, double period,
                                double workspaceScale = 1.0);

}  // namespace rp
