#pragma once
// `roboplan score`: an execution (a drilling recording, a PLUS tracked-frame sequence through a
// named transform, or a CSV of R,A,S tip points) scored against a plan's trajectory
// (rpExecutionScore.h): entry and tip offsets, angle, depth error, the largest deviation, the
// breach against a bone model, the clearance to the plan's structures at risk, the volume swept
// outside the plan's cylinder, and the deviation along depth (JSON, CSV, PNG chart).
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Exit code: 0 scored, 1 a file or the plan could not be used (the reason on `err`), 2 bad arguments.
int RunScoreCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
