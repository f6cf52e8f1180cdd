#pragma once
// `roboplan templatekey-summary <files...>`: the TemplateKey module's CLI, here (not in the
// plugin) so tests can run it in-process. Three parts: parse the options, run the module's logic
// (vtkRPTemplateKeyLogic, as the panel does), report (text, or --json).
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Returns the exit code: 0 done, 1 a file could not be read (reason on `err`), 2 bad arguments.
int RunTemplateKeySummaryCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
