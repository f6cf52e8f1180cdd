#pragma once
// `roboplan demo ...`: the Workflow module's CLI, here (not in the plugin) so tests can run it
// in-process. Parses the options into rp::DemoOptions, runs rp::RunDemo and prints where the
// report and scene went (or, with --json, one JSON object).
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Returns the exit code: 0 every stage ran, 1 a stage failed (everything done so far is kept;
/// reason on `err`), 2 bad arguments.
int RunDemoCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
