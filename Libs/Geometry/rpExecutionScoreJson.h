#pragma once
// An execution's score as JSON, with the units in the key names: what `roboplan score --json`,
// `roboplan drill --plan --json` and the demo's report.json print (the keys other tools script:
// entryOffsetMm, tipOffsetMm, angleDeg, depthErrorMm, maxDeviationMm, ...). One writer for all.
#include <nlohmann/json.hpp>

#include "rpExecutionScore.h"

namespace rp {

nlohmann::json ExecutionScoreJson(const ExecutionScore& score);

}  // namespace rp
