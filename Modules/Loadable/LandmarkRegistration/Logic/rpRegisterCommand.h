#pragma once
// `roboplan register <from fiducials> <to fiducials> --out <transform> ...`: the CLI of the
// LandmarkRegistration module, here (not in the plugin) so tests can run it in-process.
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Returns the exit code: 0 accepted and written, 1 rejected/refused/unreadable (reason on
/// `err`, and no transform file written), 2 bad arguments.
int RunRegisterCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
