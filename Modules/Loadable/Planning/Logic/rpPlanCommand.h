#pragma once
// `roboplan plan <trajectory|screw|propose|plane|show> ...`: the Planning module's CLI, here (not
// in the plugin) so tests can run it in-process. Each sub-command has three parts: parse the
// options, run the module's logic (vtkRPPlanningLogic, as the panel and the demo do), report
// (text, or --json with the units in the key names).
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Returns the exit code: 0 done, 1 the plan could not be made or measured (the reason, naming
/// the bad input, on `err`), 2 bad arguments.
int RunPlanCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
