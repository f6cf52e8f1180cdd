// Tracking module plugin: CLI commands `track`, `pivot`, `polaris-sim`.
#include "rpModule.h"

namespace {
class TrackingModule : public rp::Module {
 public:
  std::string Name() const override { return "Tracking"; }
  std::string Title() const override { return "Tracking"; }
};
}  // namespace

ROBOPLAN_DECLARE_MODULE(TrackingModule)
