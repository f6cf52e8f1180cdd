#pragma once
// A guided execution's figures as JSON (the score's keys, rpExecutionScoreJson.h, and
// enteredForbidden, drillSeconds, depthOvershootMm): what `roboplan drill --plan --json` prints
// and the demo's report.json lists under "executions". One writer for both.
#include <nlohmann/json.hpp>

#include "rpGuidedDrill.h"

namespace rp {

nlohmann::json GuidedDrillJson(const GuidedDrillResult& result);

}  // namespace rp
